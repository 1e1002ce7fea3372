//! Compiles the generated parser (src/parser.c, committed; regenerate with `tree-sitter
//! generate` in editors/tree-sitter-scn) and the nested-comment scanner.
fn main() {
    let src = std::path::Path::new("src");
    let mut c = cc::Build::new();
    c.std("c11").include(src).warnings(false);
    for file in ["parser.c", "scanner.c"] {
        let path = src.join(file);
        println!("cargo:rerun-if-changed={}", path.display());
        c.file(path);
    }
    c.compile("tree-sitter-scn");
}
