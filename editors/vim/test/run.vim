" Loads the Vim package as a user would (ftdetect, syntax, ftplugin, indent from
" editors/vim on the runtime path) and checks, in batch mode:
"  - every name `moire names --json` lists is highlighted as its kind (MOIRE_NAMES: that JSON);
"  - the sample scene's tricky places (a property that is also a keyword, a parameter that is
"    also a family, a comment);
"  - indentation (gg=G) of a flattened scene gives the scene back;
"  - commentstring, and :make through moire check (MOIRE_BINARY) into the quickfix list.
" Writes the failures to MOIRE_OUT and exits non-zero when there are any.
let s:errors = []
" The moire under test, for :make (run-test.sh sets MOIRE_BINARY).
let g:moire_program = $MOIRE_BINARY
let s:dir = fnamemodify($MOIRE_EDITORS, ':p')
execute 'set runtimepath^=' . fnameescape(s:dir . 'vim')
set hidden
filetype plugin indent on
syntax on

function! s:Group(lnum, col) abort
  return synIDattr(synID(a:lnum, a:col, 1), 'name')
endfunction

" The group of the first `word` at or after column `from` on line `lnum`.
function! s:Check(lnum, word, group, ...) abort
  let from = a:0 ? a:1 : 0
  let col = stridx(getline(a:lnum), a:word, from) + 1
  let got = s:Group(a:lnum, col)
  if col == 0 || got !=# a:group
    call add(s:errors, printf("'%s' in '%s': %s, not %s", a:word, getline(a:lnum), got, a:group))
  endif
endfunction

execute 'edit ' . fnameescape(s:dir . 'test/sample.moire')
if &filetype !=# 'moire'
  call add(s:errors, 'a .moire file has filetype ' . &filetype)
endif
call s:Check(2, 'field', 'moireKeyword')
call s:Check(2, 'bump', 'moireDeclared')
call s:Check(2, 'exp', 'moireFunction')
call s:Check(2, 'r', 'moireVariable', 15)
call s:Check(3, 'depth', 'moireParameter')
call s:Check(4, 'let', 'moireKeyword')
call s:Check(5, 'phase', 'moireProperty')
call s:Check(7, 'pingpong', 'moireWord')
call s:Check(7, 'easing', 'moireProperty')
call s:Check(7, 'sine', 'moireEasing')
call s:Check(8, 'family', 'moireProperty')
call s:Check(8, 'pencil', 'moireFamily')
call s:Check(8, 'lines', 'moireParameter')
call s:Check(8, 'field', 'moireProperty')
call s:Check(8, 'saddle', 'moireField')
call s:Check(8, 'deg', 'moireUnit')
call s:Check(8, '#18181c', 'moireColor')
call s:Check(9, 'spacing', 'moireComment')
" A param: its name, the function step in its value, then its range, step and unit; after a
" ';' the words are names again.
call s:Check(10, 'param', 'moireKeyword')
call s:Check(10, 'gap', 'moireDeclared')
call s:Check(10, 'step', 'moireFunction')
call s:Check(10, 'in', 'moireParamWord')
call s:Check(10, '0', 'moireNumber', 29)
call s:Check(10, '..', 'moireRange')
call s:Check(10, '20', 'moireNumber')
call s:Check(10, 'step', 'moireParamWord', 20)
call s:Check(10, '0.5', 'moireNumber')
call s:Check(10, 'unit', 'moireParamWord')
call s:Check(10, 'px', 'moireParamUnit')
call s:Check(11, 'bold', 'moireDeclared')
call s:Check(11, 'true', 'moireWord')
call s:Check(11, 'in', 'moireDeclared')
call s:Check(11, 'select', 'moireFunction')
if &commentstring !=# '// %s'
  call add(s:errors, 'commentstring is ' . &commentstring)
endif

" Every name, in a line that sets it off as its kind.
let s:names = json_decode(join(readfile($MOIRE_NAMES), "\n"))
let s:kinds = {'keywords': 'moireKeyword', 'properties': 'moireProperty',
      \ 'functions': 'moireFunction', 'fields': 'moireField', 'easings': 'moireEasing',
      \ 'constants': 'moireConstant', 'variables': 'moireVariable', 'words': 'moireWord'}
let s:cases = []
for [kind, group] in items(s:kinds)
  for name in s:names[kind]
    let line = kind ==# 'keywords' ? name . ' {' : kind ==# 'properties' ? name . ' = 1'
          \ : kind ==# 'functions' ? 'a = ' . name . '(1)' : 'a = ' . name
    call add(s:cases, [line, name, group, kind ==# 'properties' ? 0 : stridx(line, name)])
  endfor
endfor
for family in s:names.families
  call add(s:cases, ['family = ' . family.name, family.name, 'moireFamily', 9])
endfor
for unit in s:names.units
  call add(s:cases, ['rotation = 3' . unit, unit, 'moireUnit', 11])
endfor
enew
setfiletype moire
call setline(1, map(copy(s:cases), 'v:val[0]'))
for i in range(len(s:cases))
  let [line, name, group, from] = s:cases[i]
  call s:Check(i + 1, name, group, from)
endfor

" Indentation: the sample flattened and indented again is the sample.
let s:sample = readfile(s:dir . 'test/sample.moire')
enew
setfiletype moire
call setline(1, map(copy(s:sample), 'substitute(v:val, "^\\s*", "", "")'))
normal! gg=G
if getline(1, '$') != s:sample
  call add(s:errors, 'gg=G gives: ' . join(getline(1, '$'), ' | '))
endif

" :make reads moire check's diagnostics (the source line and caret after each are not).
" (:make and :cgetfile read the buffer's own 'errorformat'; :cexpr would read the global one.)
let s:log = tempname()
call writefile(['scene.moire:3:7: error: unknown name ''bmp''; did you mean ''bump''?',
      \ '    phase = bmp', '            ^~~', 'moire: error: cannot read ''x.moire'': No such file'],
      \ s:log)
execute 'cgetfile ' . fnameescape(s:log)
let s:qf = filter(getqflist(), 'v:val.valid')
if len(s:qf) != 1 || s:qf[0].lnum != 3 || s:qf[0].col != 7 || s:qf[0].type !=# 'e'
      \ || s:qf[0].text !~# '^unknown name'
  call add(s:errors, 'errorformat reads: ' . string(s:qf))
endif
if &l:makeprg !=# $MOIRE_BINARY . ' check %:S'
  call add(s:errors, 'makeprg is ' . &l:makeprg)
endif

" And :make itself, through the real moire, on a scene with an error.
let s:bad = tempname() . ' bad.moire'
call writefile(['layer { family = circls }'], s:bad)
execute 'edit ' . fnameescape(s:bad)
silent make
let s:qf = filter(getqflist(), 'v:val.valid')
if len(s:qf) != 1 || bufname(s:qf[0].bufnr) !=# s:bad || s:qf[0].lnum != 1 || s:qf[0].col != 18
      \ || s:qf[0].text !=# "unknown family 'circls'; did you mean 'circles'?"
  call add(s:errors, ':make gives: ' . string(s:qf))
endif
call delete(s:bad)

" No error message on the way (a script of the package that failed to load leaves one).
if v:errmsg !=# ''
  call add(s:errors, 'Vim said: ' . v:errmsg)
endif

call writefile(s:errors, $MOIRE_OUT)
if empty(s:errors)
  qall!
endif
cquit!
