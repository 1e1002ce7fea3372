//! Differential tests: the fast parser against pest (with the converter) on every `.scn` file of
//! the repository, on generated statement-dense text and on seeded mutations of all of them.
//! Both must give the same statements (spans included) and diagnostics, or both fail. The error
//! recovery, which hands the chunks that parse to the fast parser, is held to the plain one
//! (pest on every chunk) on the same mutations.

use std::path::Path;

use crate::diag::Code;
use crate::source::FileId;
use crate::syntax::{fast, parse, parse_plain, parse_with_pest};

/// Every `.scn` file under `dir`, recursively.
fn scenes(dir: &Path, out: &mut Vec<String>) {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return;
    };
    for entry in entries.flatten() {
        let path = entry.path();
        if path.is_dir() {
            scenes(&path, out);
        } else if path.extension().is_some_and(|e| e == "scn") {
            if let Ok(text) = std::fs::read_to_string(&path) {
                out.push(text);
            }
        }
    }
}

fn corpus() -> Vec<String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let mut out = Vec::new();
    scenes(&root.join("examples"), &mut out);
    scenes(&root.join("tests"), &mut out);
    assert!(out.len() > 20, "found only {} scenes", out.len());
    out.push(
        "scnc 1\nmaterial m = phong { diffuse rgb(0.5, 0.3, 0.2)  specular 0.05 }\n\
         object tree { material m  transform { rotate y 30deg  translate (1.25, 0, -2.5e1) } }\n\
         group g { transform { translate (1, 0, 0) } group a { object rock { material m } } }\n\
         let k = -(1 + 2) * --3 / 4 - 5 - -6\nlight l = area(1, 2,) { quad (1,0,0,) #fff \"a\\\"b\\n\" }\n\
         mesh t = inline { positions [1 2 3]  indices [0 0 0] } texture x = image(\"a.png\")\n\
         camera c { eye (0,0,0) /* a /* nested */ comment */ fov 30deg // line\n}\nrender{}"
            .to_string(),
    );
    out
}

fn assert_same(text: &str) {
    let fast = fast::parse(FileId(0), text);
    if crate::syntax::scan::too_deep(text).is_some() {
        // The fast parser counts depth and gives up where the scan does (pest would parse
        // the text, but no parse of a file reaches pest before the depth check).
        assert!(fast.is_none(), "{text}");
        return;
    }
    let pest = parse_with_pest(FileId(0), text).map(|(f, d)| (f.statements, d));
    if fast == pest {
        return;
    }
    // NaN literals compare unequal to themselves; their Debug forms do not.
    let (fast, pest) = (format!("{fast:#?}"), format!("{pest:#?}"));
    if fast != pest {
        let line = fast
            .lines()
            .zip(pest.lines())
            .position(|(a, b)| a != b)
            .unwrap_or(0);
        let near = |s: &str| {
            s.lines()
                .skip(line.saturating_sub(12))
                .take(16)
                .collect::<Vec<_>>()
                .join("\n")
        };
        panic!(
            "fast parser and pest differ on:\n{text}\n--- fast:\n{}\n--- pest:\n{}",
            near(&fast),
            near(&pest)
        );
    }
}

#[test]
fn fast_parser_matches_pest_on_every_scene() {
    for text in corpus() {
        assert_same(&text);
    }
}

#[test]
fn quick_depth_check_agrees_with_the_scan() {
    let deep = |open: &str, close: &str, n: usize| {
        format!(
            "scnc 1 let a = \"x\" // (\n{}1{}",
            open.repeat(n),
            close.repeat(n)
        )
    };
    for n in [47, 48, 49, 60] {
        for (open, close) in [
            ("(", ")"),
            ("[", "]"),
            ("{", "}"),
            ("/*", "*/"),
            ("( /*", "*/ )"),
        ] {
            let text = deep(open, close, n);
            let scanned = crate::syntax::scan::scan(&text).too_deep_at;
            assert_eq!(crate::syntax::scan::too_deep(&text), scanned, "{text}");
            // Inside a comment only `/*` nests: `( /*( /*...` is 1 + n deep.
            let depth = if open.len() > 2 { n + 1 } else { n };
            assert_eq!(scanned.is_some(), depth > 48, "{text}");
        }
    }
}

/// Tokens that mutations insert: every punctuation mark of the grammar, keywords, the starts of
/// comments, strings and numbers, and a few forms that make pest backtrack.
const TOKENS: &[&str] = &[
    " ",
    "\n",
    "-",
    "+",
    "*",
    "/",
    "(",
    ")",
    "{",
    "}",
    "[",
    "]",
    ",",
    "=",
    "\"",
    "\\",
    "#",
    ".",
    "1",
    "2.5",
    "1e",
    "e5",
    "deg",
    "x",
    "_",
    "/*",
    "*/",
    "//",
    "object",
    "group",
    "transform",
    "let",
    "mesh",
    "material",
    "scnc",
    "render",
    "\u{FEFF}",
    "é",
    "\t",
    "object o ",
    "transform 1",
    "f(",
    "()",
];

use crate::testing::SplitMix64 as Rng;

/// A character boundary of `text`.
fn boundary(rng: &mut Rng, text: &str) -> usize {
    let mut i = rng.below(text.len() + 1);
    while !text.is_char_boundary(i) {
        i -= 1;
    }
    i
}

fn mutate(rng: &mut Rng, text: &str) -> String {
    let mut out = text.to_string();
    for _ in 0..1 + rng.below(3) {
        let at = boundary(rng, &out);
        match rng.below(3) {
            0 => out.insert_str(at, TOKENS[rng.below(TOKENS.len())]),
            1 => {
                let mut end = (at + 1 + rng.below(4)).min(out.len());
                while !out.is_char_boundary(end) {
                    end += 1;
                }
                out.replace_range(at..end, "");
            }
            _ => {
                let from = boundary(rng, &out);
                let mut end = (from + rng.below(24)).min(out.len());
                while !out.is_char_boundary(end) {
                    end += 1;
                }
                let piece = out[from..end].to_string();
                out.insert_str(at, &piece);
            }
        }
    }
    out
}

/// The depth counted while parsing (`Cursor::counting_depth`) gives up exactly where the
/// pre-scan `scan::too_deep` did before the parse: on every text the scan finds too deep, and
/// on no other (the same statements and diagnostics as the parse of a scanned text), around
/// the limit, in every construct that nests (brackets, blocks, nested groups, block comments,
/// arrays with brackets or comment starts inside, strings with brackets), and on seeded
/// mutations of every scene.
#[test]
fn depth_counted_while_parsing_gives_up_where_the_scan_does() {
    use super::{parse_each, parse_each_from, Cursor, Fallback};
    let run = |text: &str, fallback: Fallback, counting: bool| {
        let mut statements = Vec::new();
        let diags = if counting {
            parse_each(FileId(0), text, &mut |s| statements.push(s), fallback)
        } else if crate::syntax::scan::too_deep(text).is_some() {
            None
        } else {
            let c = Cursor::new(FileId(0), text);
            parse_each_from(c, &mut |s| statements.push(s), fallback)
        };
        diags.map(|d| (statements, format!("{d:?}")))
    };
    let mut texts = Vec::new();
    for n in 44..=50 {
        let (open, close) = ("(".repeat(n), ")".repeat(n));
        let comments = "/* ".repeat(n);
        let groups = "group g { ".repeat(n);
        let ends = "} ".repeat(n);
        let nested = "/* ".repeat(3) + &" */".repeat(3);
        texts.extend([
            format!("scnc 1\nlet a = {open}1{close}\nlet b = 2\n"),
            format!("scnc 1\nlet a = f({open}1{close}, 2)\n"),
            format!("scnc 1\n{groups}object m {{ material x }} {ends}\n"),
            format!("scnc 1\n{groups}/* {nested} */ object m {{ }} {ends}\n"),
            format!("scnc 1\n{groups}object m {{ a [ 1 2 ] }} {ends}\n"),
            format!("scnc 1\n{groups}object m {{ a [ ( ] }} {ends}\nlet k = 1\n"),
            format!("scnc 1\n{groups}object m {{ a [ 1 // ] }} {ends}\n"),
            format!("scnc 1\n{groups}object m {{ a [ \"(( ] }} {ends}\n"),
            format!("scnc 1\n{groups}object m {{ a \"{open}\" }} {ends}\n"),
            format!("scnc 1\nlet a = {open}1 /* {open} */{close}\n"),
            format!("scnc 1\nlet a = {comments}1\n"),
            format!("scnc 1\nlet a = 1 {comments} */\n"),
            format!("scnc 1\nlet a = {open}1 = {close}\n"),
            format!("scnc 1\nlet a = 1 =\nlet b = {open}1{close}\n"),
            format!("scnc 1\nlet a = [ {open} ] + {open}1{close}\n"),
        ]);
    }
    let mut rng = Rng(0x5851_f42d_4c95_7f2d);
    let base = texts.clone();
    for text in base.iter().chain(corpus().iter()) {
        for _ in 0..12 {
            texts.push(mutate(&mut rng, text));
        }
    }
    let mut deep = 0;
    for text in &texts {
        deep += usize::from(crate::syntax::scan::too_deep(text).is_some());
        for fallback in [Fallback::Whole, Fallback::Line] {
            assert_eq!(
                run(text, fallback, true),
                run(text, fallback, false),
                "{text}"
            );
        }
    }
    assert!(
        deep > texts.len() / 20 && deep < texts.len() / 2,
        "{deep}/{}",
        texts.len()
    );
}

#[test]
fn fast_parser_matches_pest_on_seeded_mutations() {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut failing = 0;
    let mut total = 0;
    // `SCNC_FAST_MUTATIONS=N` runs N per scene instead (a longer hunt, by hand).
    let per_scene = std::env::var("SCNC_FAST_MUTATIONS")
        .ok()
        .and_then(|n| n.parse().ok())
        .unwrap_or(80);
    for text in corpus() {
        for _ in 0..per_scene {
            let mutated = mutate(&mut rng, &text);
            let deep = crate::syntax::scan::scan(&mutated).too_deep_at;
            assert_eq!(crate::syntax::scan::too_deep(&mutated), deep, "{mutated}");
            if deep.is_some() {
                continue;
            }
            failing += usize::from(parse_with_pest(FileId(0), &mutated).is_none());
            total += 1;
            assert_same(&mutated);
        }
    }
    // The mutations must exercise both outcomes.
    assert!(
        failing > total / 10 && failing < total * 9 / 10,
        "{failing}/{total}"
    );
}

/// The error recovery with the fast parser on the chunks that parse gives what the plain one
/// (pest on every chunk) gives: the same statements, spans included, and the same diagnostics
/// in order, on seeded mutations of every scene (one to three edits each, so some have several
/// broken statements). The compile is a function of these (the driver checks the statements
/// and adds the diagnostics), so its IR and diagnostics are the same too.
#[test]
fn recovery_with_fast_chunks_matches_the_plain_recovery() {
    let mut rng = Rng(0x5eed_c4a2_11b0_22d1);
    let (mut broken, mut total, mut unclosed) = (0, 0, 0);
    let mut scenes = corpus();
    scenes.push(object_lines(&mut rng));
    for text in scenes {
        for k in 0..60 {
            // Every third variant of the object lines also has one of them cut inside its
            // braces, a `{` left open over every later object (`tail.rs`).
            let mutated = match k % 3 {
                0 if text.contains("object o0 ") => cut_object_line(&mut rng, &text),
                _ => mutate(&mut rng, &text),
            };
            let (file, diags) = parse(FileId(0), &mutated).into_parts();
            let statements = file.unwrap_or_default().statements;
            let (plain, plain_diags) = parse_plain(FileId(0), &mutated);
            // Debug forms: NaN literals compare unequal to themselves.
            assert_eq!(
                format!("{statements:#?}\n{diags:#?}"),
                format!("{:#?}\n{plain_diags:#?}", plain.statements),
                "recoveries differ on:\n{mutated}"
            );
            broken += usize::from(diags.iter().any(crate::diag::Diagnostic::is_error));
            let open = |d: &crate::diag::Diagnostic| d.code == Code::SyntaxUnclosedDelimiter;
            unclosed += usize::from(diags.iter().any(open));
            total += 1;
        }
    }
    assert!(broken > total / 4, "only {broken} of {total} broken");
    assert!(unclosed >= 20, "only {unclosed} with a `{{` never closed");
}

/// A generated scene of `object` lines (some in groups, some nested over several lines), with a
/// declaration among them, as exporters write.
fn object_lines(rng: &mut Rng) -> String {
    let mut s = String::from("scnc 1\nmaterial m = phong { diffuse #fff }\n");
    for i in 0..40 {
        match rng.below(8) {
            0 => s.push_str(&format!(
                "group g{i} {{ transform {{ translate (0, {i}, 0) }}\n  object ball {{ material m }}\n}}\n"
            )),
            1 => s.push_str("// a comment\nlight l = point { position (0, 1, 0) }\n"),
            _ => {}
        }
        s.push_str(&format!(
            "object o{i} {{ material m  transform {{ rotate y {i}deg  translate ({i}, 1, 2) }} }}\n"
        ));
    }
    s
}

/// `text` with one of its `object` lines cut at a random place inside it (and a newline).
fn cut_object_line(rng: &mut Rng, text: &str) -> String {
    let lines: Vec<usize> = text.match_indices("\nobject").map(|(i, _)| i + 1).collect();
    let at = lines[rng.below(lines.len())];
    let line_end = text[at..].find('\n').map_or(text.len(), |n| at + n);
    let cut = at + 1 + rng.below(line_end - at - 1);
    format!("{}\n{}", &text[..cut], &text[line_end..])
}

/// A statement cut inside its braces, which pest fails to parse before the next line that
/// starts a word: `fails_over_a_run`'s verdict (pest would fail on it in the whole text,
/// told without reading the `object`s after it) is pest's, on seeded cuts of object lines
/// (with tokens typed after the cut, and a `}` line or an `include` line that may close or
/// continue the open block later on), and the whole-file parse is pest's.
#[test]
fn a_cut_statements_failure_is_told_over_the_run_after_it() {
    let mut rng = Rng(0xC07_5EED);
    let (mut told, mut total) = (0, 0);
    let extras = [
        "",
        " (1, 2",
        " [1 2",
        " /* c",
        " \"str",
        " =",
        " }",
        " object q {",
        " { {",
    ];
    let later = [
        "}\n",
        "include \"a.scn\"\n",
        "/* a comment */\n",
        "}}\n",
        "object box { points [1 2 3] }\n",
        "object box { points [1 2 3] }  object box { }\n",
        "",
    ];
    for _ in 0..400 {
        let text = object_lines(&mut rng);
        let lines: Vec<usize> = text.match_indices("\nobject").map(|(i, _)| i + 1).collect();
        let at = lines[rng.below(lines.len())];
        let line_end = text[at..].find('\n').map_or(text.len(), |n| at + n);
        let cut = at + 1 + rng.below(line_end - at - 1);
        let mut rest = text[line_end..].to_string();
        let more = later[rng.below(later.len())];
        let lines_after: Vec<usize> = rest.match_indices('\n').map(|(i, _)| i + 1).collect();
        // Near the cut: inside the run after it, more often than not.
        let put = lines_after[rng.below(lines_after.len().min(4))];
        rest.insert_str(put.min(rest.len()), more);
        let mutated = format!(
            "{}{}\n{rest}",
            &text[..cut],
            extras[rng.below(extras.len())]
        );
        if crate::syntax::scan::too_deep(&mutated).is_some() {
            continue;
        }
        total += 1;
        assert_same(&mutated);
        if super::fails_over_a_run(FileId(0), &mutated, at) {
            use pest::Parser;
            let whole =
                crate::syntax::SceneParser::parse(crate::syntax::Rule::statement, &mutated[at..]);
            assert!(
                whole.is_err(),
                "told to fail, but pest parses it:\n{mutated}"
            );
            told += 1;
        }
    }
    eprintln!("{told} of {total} told");
    assert!(told >= 120, "only {told} of {total} told");
}

/// A `let` and a block-less declaration end at their last token (both parsers): the blanks
/// and comments after them, which pest's rules skip while looking for more, are not theirs.
#[test]
fn a_statement_span_ends_at_its_last_token() {
    let text =
        "scnc 1\nlet a = 1  // one\n\nlet b = a + 2 /* two */\nmesh m = quad  \n\n// after\n";
    for statements in [
        fast::parse(FileId(0), text).map(|(s, _)| s),
        parse_with_pest(FileId(0), text).map(|(f, _)| f.statements),
    ] {
        let statements = statements.expect("parses");
        let texts: Vec<&str> = statements
            .iter()
            .map(|s| &text[s.span().start as usize..s.span().end as usize])
            .collect();
        assert_eq!(
            texts,
            ["scnc 1", "let a = 1", "let b = a + 2", "mesh m = quad"]
        );
    }
}
