; Bracket pairs for Zed.
("{" @open "}" @close)
("(" @open ")" @close)
