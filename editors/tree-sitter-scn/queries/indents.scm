;; Indents for scnc scene files (Neovim nvim-treesitter capture names): a block indents its
;; items; its closing brace goes back.
(block) @indent.begin
(block "}" @indent.branch)
(block "}" @indent.end)
(block_comment) @indent.auto
