; Indents for Zed: a block indents its items.
(block "}" @end) @indent
