" Indentation for .moire scenes: one level inside each open { or (, back out at the line
" that closes it.
if exists('b:did_indent')
  finish
endif
let b:did_indent = 1

setlocal indentexpr=MoireIndent(v:lnum)
setlocal indentkeys=0},0),!^F,o,O
setlocal nosmartindent nocindent
let b:undo_indent = 'setlocal indentexpr< indentkeys< smartindent< cindent<'

if exists('*MoireIndent')
  finish
endif

" The brackets a line opens less those it closes, comments left out.
function! s:Balance(line) abort
  let text = substitute(a:line, '//.*$', '', '')
  let text = substitute(text, '/\*.\{-}\*/', '', 'g')
  let opened = len(substitute(text, '[^{(]', '', 'g'))
  let closed = len(substitute(text, '[^})]', '', 'g'))
  return opened - closed
endfunction

" How many closing brackets begin the line.
function! s:Leading(line) abort
  return len(substitute(matchstr(a:line, '^\s*[})\t ]*'), '[^})]', '', 'g'))
endfunction

" The previous line's indent, one level in after a line that leaves a bracket open (its
" leading closers were already counted out of its own indent), one out after a line that
" closes one opened above it, and one out on a line that starts by closing.
function! MoireIndent(lnum) abort
  let prev = prevnonblank(a:lnum - 1)
  if prev == 0
    return 0
  endif
  let net = s:Balance(getline(prev)) + s:Leading(getline(prev))
  let ind = indent(prev) + shiftwidth() * (net > 0 ? 1 : net < 0 ? -1 : 0)
  if s:Leading(getline(a:lnum)) > 0
    let ind -= shiftwidth()
  endif
  return max([ind, 0])
endfunction
