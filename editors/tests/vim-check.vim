" Editor support: the Vim syntax over examples/ and a probe. Run headless:
"   vim -Nu NONE -Es -S editors/tests/vim-check.vim -- FILES...
" Prints `file:line:col group` for every character highlighted as an error, then
" `vim: N errors`; exits non-zero when an example has an error or the probe has none.
set runtimepath^=editors/vim
filetype on
syntax on
let s:errors = 0
function! s:Check(expect_error) abort
  let found = 0
  for l in range(1, line('$'))
    let text = getline(l)
    for c in range(1, len(text))
      if synIDattr(synIDtrans(synID(l, c, 1)), 'name') ==# 'Error'
        let found += 1
        if !a:expect_error
          call writefile([expand('%') . ':' . l . ':' . c . ' ' . synIDattr(synID(l, c, 1), 'name')], '/dev/stderr', 'a')
        endif
      endif
    endfor
  endfor
  return found
endfunction
for f in argv()
  execute 'edit ' . fnameescape(f)
  if &filetype !=# 'scn'
    call writefile([f . ': filetype not detected'], '/dev/stderr', 'a')
    let s:errors += 1
  endif
  let s:errors += s:Check(0)
endfor
let s:probe = tempname() . '.scn'
call writefile(['camera c { fov 40deg ; eye 12px }'], s:probe)
execute 'edit ' . fnameescape(s:probe)
if s:Check(1) != 3
  call writefile(['probe: the stray `;` and the unit `px` were not both flagged'], '/dev/stderr', 'a')
  let s:errors += 1
endif
call writefile(['vim: ' . s:errors . ' errors'], '/dev/stderr', 'a')
execute (s:errors == 0 ? 'qall!' : 'cquit!')
