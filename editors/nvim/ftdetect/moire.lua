-- .moire scenes. Neovim 0.8 and later read vim.filetype.add; 0.7 reads it only with
-- g:do_filetype_lua set, so the autocommand (in the filetypedetect group this file is
-- sourced in) is kept for it. Both agree, and setfiletype sets a buffer's type once.
if vim.filetype and vim.filetype.add then
  vim.filetype.add({ extension = { moire = 'moire' } })
end
vim.cmd([[autocmd BufNewFile,BufRead *.moire setfiletype moire]])
