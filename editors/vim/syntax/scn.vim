" Vim syntax file
" Language: scnc scene files (.scn); reference: grammar/README.md
" Word lists are checked against the compiler's tables by tests/editors_drift.rs: each list is
" one group of `syn keyword` lines (scnKeyword, scnKey, scnKind, scnWord, scnFunction,
" scnColorFunction) plus the unit pattern (scnUnit).

if exists("b:current_syntax")
  finish
endif

syn iskeyword @,48-57,_

" Stray characters first, so that every rule below takes precedence.
syn match scnInvalid /[^[:space:][:alnum:]_{}()\[\],=+\-*\/"#.]/

" Statement and nested-block keywords.
syn keyword scnKeyword scnc include let camera material texture mesh light object group
syn keyword scnKeyword render transform

" Property keys of every block kind (the checker decides which block takes which).
syn keyword scnKey contained ambient camera color diffuse encoding even exposure eye filter fov
syn keyword scnKey contained image indices intensity light_samples look_at material matrix mesh mtl normal_green normal_map
syn keyword scnKey contained normal_strength normals odd output position positions quad radiance radius resolution
syn keyword scnKey contained rotate samples scale seed segments shininess size specular target tonemap
syn keyword scnKey contained subdivisions translate two_sided up uvs visible wrap
syn keyword scnKey contained quality noise max_samples

" Kinds after `=`: `phong`, `sphere`, `image(\"file\")`, ...
syn keyword scnKind area box checker constant environment image inline obj phong point
syn keyword scnKind icosphere quad sphere

" Bare words some keys take: `wrap repeat`, `tonemap filmic`.
syn keyword scnWord contained anisotropic bilinear clamp data directx filmic grid mirror nearest opengl reinhard
syn keyword scnWord contained repeat rgss srgb trilinear
syn keyword scnWord contained draft preview final

syn keyword scnBoolean true false

" Built-in functions; the colour constructors among them.
syn keyword scnFunction sin cos tan sqrt abs min max pow radians degrees
syn keyword scnFunction normalize length dot cross
syn keyword scnColorFunction rgb linear srgb

" Declared names: `camera main`, `material wall =`, `let red =`, `group row`.
" Top-level statements start in column 0; groups also nest.
syn match scnDeclared /\(^\(let\|camera\|material\|texture\|mesh\|light\)\s\+\|^\s*group\s\+\)\@<=\h\w*/

" Numbers with an optional unit; any other suffix is an error.
syn match scnNumber /\<\d\+\(\.\d*\)\=\([eE][+-]\=\d\+\)\=/ nextgroup=scnUnit,scnBadUnit
syn match scnNumber /\.\d\+\([eE][+-]\=\d\+\)\=/ nextgroup=scnUnit,scnBadUnit
syn match scnBadUnit /\h\w*/ contained
syn match scnUnit /\(deg\|rad\)\>/ contained

syn match scnBadColor /#\w*/
syn match scnColor /#\x\{6}\>\|#\x\{3}\>/

syn match scnEscape /\\./ contained
syn region scnString start=/"/ skip=/\\./ end=/"/ end=/$/ contains=scnEscape oneline

syn region scnArray matchgroup=scnDelimiter start=/\[/ end=/\]/ contains=scnNumber,scnInvalid
syn region scnBlock matchgroup=scnDelimiter start=/{/ end=/}/ contains=@scnBlockItems fold transparent

syn cluster scnBlockItems contains=scnInvalid,scnKeyword,scnKey,scnKind,scnWord,scnBoolean,scnFunction,scnColorFunction,scnDeclared,scnNumber,scnColor,scnBadColor,scnString,scnArray,scnBlock,scnOperator,scnComment,scnBlockComment

syn match scnOperator /[=+\-*\/]/
syn match scnComment "//.*$" contains=@Spell
syn region scnBlockComment start="/\*" end="\*/" contains=scnBlockComment,@Spell fold

hi def link scnKeyword Keyword
hi def link scnKey Identifier
hi def link scnKind Type
hi def link scnWord Constant
hi def link scnBoolean Boolean
hi def link scnFunction Function
hi def link scnColorFunction Function
hi def link scnDeclared Function
hi def link scnNumber Number
hi def link scnUnit Special
hi def link scnBadUnit Error
hi def link scnColor Constant
hi def link scnBadColor Error
hi def link scnString String
hi def link scnEscape SpecialChar
hi def link scnDelimiter Delimiter
hi def link scnOperator Operator
hi def link scnComment Comment
hi def link scnBlockComment Comment
hi def link scnInvalid Error

let b:current_syntax = "scn"
