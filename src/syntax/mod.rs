//! Stage 1, syntax: `.scn` text → AST (`SceneFile`), every node spanned. Errors: `ParseError`.
