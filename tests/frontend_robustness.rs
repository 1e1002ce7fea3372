//! Robustness of the front end: thousands of seeded mutations of the examples (byte flips,
//! truncations, duplicated ranges, inserted tokens) and random token soups go through
//! `compile_source` / `compile_file`. Nothing may panic or hang, and every failed compile must
//! carry at least one error diagnostic whose spans lie inside their files.

use std::time::{Duration, Instant};

use scnc::assets::MemLoader;
use scnc::compile::{compile_file, compile_source, Compiled};

/// xorshift64*: a tiny deterministic generator (no dependency needed).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }

    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

const TOKENS: &[&str] = &[
    "{",
    "}",
    "(",
    ")",
    "[",
    "]",
    "\"",
    "/*",
    "*/",
    "//",
    "#",
    "#zz",
    "-",
    "+",
    "*",
    "/",
    ",",
    "=",
    "deg",
    "rad",
    "30deg",
    "1e999",
    "0.0",
    "-1",
    "1/0",
    "nan",
    "x",
    "y",
    "object",
    "group g {",
    "let",
    "let q = ",
    "camera",
    "material",
    "mesh",
    "light",
    "render",
    "include \"a.scn\"",
    "transform {",
    "rotate",
    "scale 0",
    "matrix [1 0 0]",
    "positions [(0,0,0)]",
    "indices [9]",
    "sqrt(-1)",
    "srgb(",
    "rgb(1,2)",
    "normalize((0,0,0))",
    "\u{0}",
    "é",
    "\u{feff}",
    "\n",
    "scnc 1",
    "scnc 2",
    "samples 3",
    "resolution 0 x 0",
    "fov 0deg",
    "((((((((((",
    "))))))))",
    "sphere",
    "segments 1e9",
    "inline",
    "area",
    "point",
    "environment",
    "true",
    "false",
];

fn examples() -> Vec<(String, String)> {
    let dir = concat!(env!("CARGO_MANIFEST_DIR"), "/examples");
    let mut out = Vec::new();
    for entry in std::fs::read_dir(dir).expect("examples folder exists") {
        let path = entry.expect("readable").path();
        if path.extension().and_then(|e| e.to_str()) == Some("scn") {
            let text = std::fs::read_to_string(&path).expect("examples are UTF-8");
            let name = format!(
                "examples/{}",
                path.file_name().and_then(|n| n.to_str()).unwrap_or("x.scn")
            );
            out.push((name, text));
        }
    }
    out.sort();
    out
}

fn loader() -> MemLoader {
    let mut l = MemLoader::new();
    let lib = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/lib/materials.scn");
    l.insert(
        "examples/lib/materials.scn",
        std::fs::read(lib).expect("library exists"),
    );
    l.insert("examples/a.scn", b"scnc 1\ninclude \"a.scn\"\n".to_vec());
    l
}

fn mutate(rng: &mut Rng, base: &[u8]) -> Vec<u8> {
    let mut b = base.to_vec();
    for _ in 0..1 + rng.below(4) {
        let len = b.len();
        match rng.below(5) {
            0 if len > 0 => {
                let i = rng.below(len);
                b[i] = rng.next() as u8;
            }
            1 => b.truncate(rng.below(len + 1)),
            2 if len > 0 => {
                let s = rng.below(len);
                let e = (s + rng.below(200)).min(len);
                let piece = b[s..e].to_vec();
                let at = rng.below(len + 1);
                b.splice(at..at, piece);
            }
            3 if len > 0 => {
                let s = rng.below(len);
                let e = (s + rng.below(50)).min(len);
                b.drain(s..e);
            }
            _ => {
                let tok = TOKENS[rng.below(TOKENS.len())];
                let at = rng.below(len + 1);
                b.splice(at..at, format!(" {tok} ").into_bytes());
            }
        }
    }
    b
}

fn soup(rng: &mut Rng) -> String {
    let mut s = String::from(if rng.below(2) == 0 { "scnc 1\n" } else { "" });
    for _ in 0..rng.below(60) {
        s.push_str(TOKENS[rng.below(TOKENS.len())]);
        s.push(if rng.below(4) == 0 { '\n' } else { ' ' });
    }
    s
}

fn assert_sound(c: &Compiled, input: &[u8]) {
    if c.scene.is_none() {
        assert!(
            c.diagnostics.iter().any(|d| d.is_error()),
            "failed without an error for input {:?}",
            String::from_utf8_lossy(input)
        );
    } else {
        assert!(!c.diagnostics.iter().any(|d| d.is_error()));
    }
    for d in &c.diagnostics {
        for l in d.primary.iter().chain(&d.secondary) {
            let text = &c.sources.get(l.span.file).text;
            assert!(
                text.get(l.span.range()).is_some(),
                "span {:?} outside or splitting its file; input {:?}",
                l.span,
                String::from_utf8_lossy(input)
            );
        }
        // Rendering must not panic either.
        let _ = scnc::diag::render_plain(d, &c.sources, 100);
    }
}

#[test]
fn mutated_examples_and_token_soups_never_panic() {
    let bases = examples();
    let loader = loader();
    // SCNC_FUZZ_SEED explores other seeds locally; CI uses the fixed one.
    let seed = std::env::var("SCNC_FUZZ_SEED")
        .ok()
        .and_then(|s| s.parse::<u64>().ok())
        .unwrap_or(0x5eed_1234_abcd_0001);
    let mut rng = Rng(seed | 1);
    let start = Instant::now();
    let mut cases = 0;
    while cases < 4000 && start.elapsed() < Duration::from_secs(6) {
        let input: Vec<u8> = if cases % 5 == 4 {
            soup(&mut rng).into_bytes()
        } else {
            let (_, text) = &bases[rng.below(bases.len())];
            mutate(&mut rng, text.as_bytes())
        };
        let compiled = if cases % 7 == 0 {
            // Raw bytes through a loader: exercises the binary / UTF-8 checks.
            let mut l = loader_with(&input);
            l.insert("examples/lib/materials.scn", lib_bytes());
            compile_file(std::path::Path::new("examples/fuzz.scn"), &l)
        } else {
            compile_source(
                "examples/fuzz.scn",
                &String::from_utf8_lossy(&input),
                &loader,
            )
        };
        assert_sound(&compiled, &input);
        cases += 1;
    }
    assert!(cases >= 500, "only {cases} cases ran in the time budget");
}

fn lib_bytes() -> Vec<u8> {
    std::fs::read(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/lib/materials.scn"
    ))
    .expect("library exists")
}

fn loader_with(input: &[u8]) -> MemLoader {
    let mut l = MemLoader::new();
    l.insert("examples/fuzz.scn", input.to_vec());
    l
}

#[test]
fn pathological_inputs_are_diagnostics() {
    let loader = MemLoader::new();
    let long_chain = format!("scnc 1\nlet a = 1{}\n", " + 1".repeat(200));
    let cases = [
        String::new(),
        "scnc 1".to_string(),
        "\u{feff}scnc 1\n".to_string(),
        format!("scnc 1\nlet a = {}1{}\n", "(".repeat(47), ")".repeat(47)),
        format!("scnc 1\nlet a = {}1\n", "-".repeat(100_000)),
        format!("scnc 1\n{}\n", "/*".repeat(10_000)),
        format!("scnc 1\n{}", "group g {".repeat(47) + &"}".repeat(47)),
        format!("scnc 1\nlet a = 1{}\n", " + 1".repeat(100_000)),
        long_chain,
        "scnc 1\nmesh m = inline { positions [".to_string(),
        "scnc 1\nlet a = \"unterminated\n".to_string(),
        "scnc 1e400".to_string(),
    ];
    for text in cases {
        let c = compile_source("p.scn", &text, &loader);
        assert_sound(&c, text.as_bytes());
        assert!(c.scene.is_none(), "no camera: must fail");
    }
}
