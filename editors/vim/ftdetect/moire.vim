" .moire scenes (Vim and Neovim).
autocmd BufNewFile,BufRead *.moire setfiletype moire
