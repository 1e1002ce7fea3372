//! Diagnostics: the bag of errors and warnings a compile produces, and how they are printed.
