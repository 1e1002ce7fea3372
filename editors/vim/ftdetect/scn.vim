" scnc scene files
autocmd BufRead,BufNewFile *.scn setfiletype scn
