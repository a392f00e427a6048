" Filetype settings for .moire scenes: comments, :make through `moire check`, whose
" diagnostics (file:line:col: error: message) fill the quickfix list, and gq through the
" formatter, `moire fmt -`.
if exists('b:did_ftplugin')
  finish
endif
let b:did_ftplugin = 1

setlocal commentstring=//\ %s
setlocal comments=s1:/*,mb:*,ex:*/,://
setlocal formatoptions-=t formatoptions+=croql
setlocal expandtab shiftwidth=4 softtabstop=4
setlocal iskeyword=a-z,A-Z,48-57,_

" `moire` on PATH, or g:moire_program. The source line and caret after each diagnostic,
" and moire's own lines (moire: error: cannot read ...), are not places in a file.
let &l:makeprg = get(g:, 'moire_program', 'moire') . ' check %:S'
let &l:formatprg = get(g:, 'moire_program', 'moire') . ' fmt -'
setlocal errorformat=%f:%l:%c:\ %trror:\ %m,%f:%l:%c:\ %tarning:\ %m,%f:%l:%c:\ %tote:\ %m,%-G%.%#

let b:undo_ftplugin = 'setlocal commentstring< comments< formatoptions< expandtab< shiftwidth<'
      \ . ' softtabstop< iskeyword< makeprg< errorformat< formatprg<'
