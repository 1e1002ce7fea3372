;; Folds for scnc scene files: blocks and block comments.
[
  (block)
  (block_comment)
] @fold
