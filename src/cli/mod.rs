//! The command line: runs the pipeline once (`render`, `check`, `ir`) or in a loop (`watch`).
//! Only this module prints.
