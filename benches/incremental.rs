//! Incremental re-checking benchmark (a program, not a test): `cargo bench --bench incremental
//! [-- --edits N (rounded up to even)] [-- --objects N] [-- --no-watch] [-- --in-place] [-- --only Uses,BadValue]
//! [-- --split N]`.
//!
//! The scene of issue 22: 100,000 `object` statements, each with a rotate and a translate, over
//! three meshes, an OBJ mesh and an image texture (placed by the group) and 100 materials that
//! name one constant, `gloss`, and one `group` (about 9 MB). Forty-two kinds
//! of edit, one line each: one object's translate in the middle of the file (a person nudging one
//! object), one material's colour, the value of `gloss` (its 100 materials re-checked), an
//! `object` line inserted, one deleted, an object's material misspelt then put back (every
//! other edit an error: what the language server sees while the user types; `scnc watch`
//! builds nothing then, so its figure is save → the `error` event), a `let` nothing names inserted then deleted, and two
//! syntax errors, each then taken out: a stray `=` in an object's line, and an object's line
//! cut inside its braces (a `{` left open to the end of the file); an object's material set to
//! one nothing else uses (`spare`: used, then unused again when put back; the IR's indices
//! change both times), and a material's albedo set above 1 (an error, the material not
//! lowered) and put back; a material nothing names inserted (unused: a
//! warning) and deleted; `gloss` given an error (its materials fail quietly) and put back; the camera's eye, the light's intensity and the render block's sample
//! count changed (one number each); the constant the camera's `fov` names changed; a group of two objects (one in a nested group) lifted; material `m5`
//! renamed (its 1,000 objects then name an unknown material) and named back; a stray `=` typed into `let gloss` and into one material's
//! line (syntax errors that lose a constant and a declaration others name), each taken out;
//! (2026-11-26, fifth session) the OBJ mesh's file changed, the image texture's wrap mode
//! changed, the light and the camera renamed, a group added and removed, and material `m0`
//! (named by the group and 1,000 objects) renamed and named back; (sixth session) `let gloss`
//! renamed (its 100 materials fail) and named back, a block of three declarations pasted and
//! deleted, the OBJ mesh's material override changed, and a material the group names added
//! after the group named it; (seventh session) material `m5`'s line deleted (its 1,000 objects
//! then name an unknown material) and put back, and a material pasted with two objects that
//! name it, then deleted; (ninth session) a second light added and deleted, the light's
//! intensity set to -1 (an error) and put back, and `let lens` (the camera names it) renamed
//! and named back; (twelfth session) a second `material m5` added (a duplicate-name error)
//! and deleted; (thirteenth session) the first `let gloss` edited while a second one stands
//! (in process only: the duplicate-name error stands through every edit); (fourteenth
//! session) `include "part_extra.scn"` (1,000 objects) added and deleted; (fifteenth session)
//! an object's line, the unused `material spare`'s and `let gloss`'s commented out and
//! uncommented; (seventeenth session) a `let` right after `let gloss` commented out and
//! uncommented, and an include pointed at another file and back; (eighteenth session) an
//! include inserted at the file's start while another file is read after it, and deleted.
//!
//! 1. Front end, in process: a full `compile_with` beside `compile::Incremental::compile` after
//!    each edit (the text served from memory; diagnostics are ready when it returns).
//! 2. `scnc watch --events json --no-serve` (the release binary, a real process) on the file,
//!    saved by a rename into place (or with `--in-place` by a plain `fs::write`):
//!    save → `checked` event (the front end's diagnostics, before the build), save →
//!    `compiled` event (after the build) and save → first `pass` event (the preview
//!    image is written before that event), with the compile, build and pass times it reports;
//!    for the errors, save → `error` event (the diagnostics), and for the edit taking each out,
//!    save → `checked` and save → first `pass`.
//!
//! `--split N` (2026-11-26, sixth session): the same scene written as a root file and `N`
//! included files of objects (`files_of`); each save writes only the files that changed, and the
//! kinds of edit that keep the lines in place and the syntax whole are run.
//!
//! Medians (and the slowest) per kind of edit are printed; figures go to docs/watch.md by hand.

// A global allocator needs `unsafe impl`; it only forwards to the system allocator.
#![allow(unsafe_code)]

use std::path::Path;
use std::sync::atomic::Ordering;
use std::time::{Duration, Instant};

use scnc::assets::MemLoader;
use scnc::compile::{compile_with, Incremental, Overrides, Reuse};
use scnc::scene::{self, BuildCache, BuildOptions};
use scnc::source::SourceMap;

#[path = "support/watch_process.rs"]
mod watch_process;
use watch_process::WatchProcess;

#[path = "support/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::{Counting, CURRENT, PEAK};

#[global_allocator]
static ALLOC: Counting = Counting;

/// The scene's lines; object `i` is line `HEADER + i`.
fn scene(objects: usize) -> Vec<String> {
    let mut s = vec![
        "scnc 1".to_string(),
        camera_line(500),
        render_line(4),
        "mesh tree = icosphere { radius 1  subdivisions 1 }".into(),
        "mesh rock = box { size (1, 0.5, 1) }".into(),
        "mesh post = box { size (0.2, 2, 0.2) }".into(),
        let_line(0),
    ];
    s.extend((0..100).map(|m| material_line(m, m % 10)));
    // Unused (a warning) until a `Uses` edit names it.
    s.push("material spare = phong { diffuse #808080 }".into());
    // An OBJ mesh and an image texture, placed by the group.
    s.push(obj_line(0));
    s.push(image_line(0));
    s.push("material grainy = phong { diffuse grain  specular 0.1 }".into());
    s.push(group_line(0));
    debug_assert_eq!(s.len(), HEADER);
    s.extend((0..objects).map(|i| object_line(i, 0)));
    s.push(lens_line(0));
    s.push(light_line(100_000));
    s
}

/// The camera, its eye at `x`.
fn camera_line(x: usize) -> String {
    format!("camera main {{ eye ({x}, 80, -300)  target (500, 0, 50)  fov lens }}")
}

/// The constant the camera's `fov` names (the line before the light), at its `k`-th value.
fn lens_line(k: usize) -> String {
    format!("let lens = {}deg", 40 + k % 30)
}

/// The render block, with `samples` samples per pixel.
fn render_line(samples: usize) -> String {
    format!("render {{ resolution 640 x 360  samples {samples} }}")
}

/// The light (the file's last line), of `intensity`.
fn light_line(intensity: usize) -> String {
    format!("light sun = point {{ position (500, 100, 0)  intensity {intensity} }}")
}

/// A group of two objects, one in a nested group (the OBJ mesh, with the image texture), lifted
/// by `y`.
fn group_line(y: usize) -> String {
    format!(
        "group cluster {{ transform {{ translate (500, {y}, 50) }}  object tree {{ material m0 }}  \
         group twig {{ object crate {{ material grainy  transform {{ scale 2 }} }} }} }}"
    )
}

/// The OBJ mesh, its `k`-th version: `crate_a.obj` and `crate_b.obj` in turn.
fn obj_line(k: usize) -> String {
    format!("mesh crate = obj(\"crate_{}.obj\")", ["a", "b"][k % 2])
}

/// The image texture, its `k`-th version: another wrap mode each time.
fn image_line(k: usize) -> String {
    let wrap = ["repeat", "clamp", "mirror"][k % 3];
    format!("texture grain = image(\"grain.png\") {{ wrap {wrap} }}")
}

/// A group added after the other (edits 0, 2, 4, …), one object in it.
fn added_group_line(k: usize) -> String {
    format!("group added{k} {{ object rock {{ material m{}  transform {{ translate (0, {k}, 0) }} }} }}", k % 100)
}

/// The assets the scene reads: two versions of a cube OBJ and a 4×4 PNG.
fn assets() -> Vec<(&'static str, Vec<u8>)> {
    let cube = |s: f32| {
        let mut obj = String::new();
        for i in 0..8 {
            let c = |b: usize| if i >> b & 1 == 1 { s } else { -s };
            obj += &format!("v {} {} {}\n", c(0), c(1), c(2));
        }
        for f in [
            "1 3 4 2", "5 6 8 7", "1 2 6 5", "3 7 8 4", "1 5 7 3", "2 4 8 6",
        ] {
            obj += &format!("f {f}\n");
        }
        obj.into_bytes()
    };
    let mut png = Vec::new();
    let image = image::RgbImage::from_fn(4, 4, |x, y| {
        image::Rgb([(x * 60) as u8, (y * 60) as u8, 90])
    });
    image
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .expect("a PNG in memory");
    let mut part = String::from("scnc 1\n");
    for i in 0..EXTRA_OBJECTS {
        part.push_str(&object_line(i * 7, 3));
        part.push('\n');
    }
    let mut other = String::from("scnc 1\n");
    for i in 0..EXTRA_OBJECTS {
        other.push_str(&object_line(i * 7 + 3, 5));
        other.push('\n');
    }
    vec![
        ("part_extra.scn", part.into_bytes()),
        ("part_other.scn", other.into_bytes()),
        ("crate_a.obj", cube(0.5)),
        ("crate_b.obj", cube(0.7)),
        ("grain.png", png),
    ]
}

const HEADER: usize = 112;
/// The objects of `part_extra.scn`, which [`Kind::Include`] includes.
const EXTRA_OBJECTS: usize = 1000;
/// The lines of the group, the OBJ mesh and the image texture.
const GROUP_LINE: usize = 111;
const OBJ_LINE: usize = 108;
const IMAGE_LINE: usize = 109;
/// The lines of the camera and the render block.
const CAMERA_LINE: usize = 1;
const RENDER_LINE: usize = 2;
/// The line of the `let` every material names, and of the first material.
const LET_LINE: usize = 6;
const FIRST_MATERIAL: usize = 7;

/// The constant the materials' `specular` names, at its `k`-th value.
fn let_line(k: usize) -> String {
    format!("let gloss = 0.{:02}", 5 + k % 90)
}

/// Material `m`, with red `0.shade`.
fn material_line(m: usize, shade: usize) -> String {
    format!("material m{m} = phong {{ diffuse rgb(0.{shade}, 0.3, 0.2)  specular gloss }}")
}

/// Object `i`, lifted by `y`.
/// The lines of `text` (one statement each in these scenes) that name one of `names` as a
/// whole word (letters, digits and `_` on neither side), as the incremental compile's search
/// finds them.
fn lines_naming(text: &str, names: &[&str]) -> usize {
    let word = |c: char| c.is_ascii_alphanumeric() || c == '_';
    text.lines()
        .filter(|l| l.split(|c| !word(c)).any(|w| names.contains(&w)))
        .count()
}

fn object_line(i: usize, y: usize) -> String {
    let meshes = ["tree", "rock", "post"];
    format!(
        "object {} {{ material m{}  transform {{ rotate y {}deg  translate ({}.25, {y}, {}.5) }} }}",
        meshes[i % 3],
        i % 100,
        i % 360,
        i % 1000,
        i / 1000
    )
}

/// What an edit changes: one line of text each time.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Kind {
    /// One object near the middle (another one each time) is lifted.
    Object,
    /// One material's colour changes (another material each time).
    Material,
    /// The constant `gloss`, which every material names, changes.
    Let,
    /// An `object` line (a copy of one near the middle) is inserted beside it.
    Insert,
    /// An `object` line near the middle is deleted.
    Delete,
    /// Edits 0, 2, 4, …: one object's material misspelt (an error); 1, 3, 5, …: put back.
    Typo,
    /// Edits 0, 2, 4, …: a `let` nothing names inserted after `gloss`; 1, 3, 5, …: deleted.
    UnusedLet,
    /// Edits 0, 2, 4, …: a stray `=` typed into one object's line (a syntax error, the line's
    /// braces still balanced); 1, 3, 5, …: taken out.
    Stray,
    /// Edits 0, 2, 4, …: one object's line cut inside its braces (a syntax error that leaves a
    /// `{` open to the end of the file, as a statement being typed does); 1, 3, 5, …: put back.
    Cut,
    /// Edits 0, 2, 4, …: one object's material set to `spare`, which nothing else uses (it
    /// becomes used: the IR's material indices change); 1, 3, 5, …: put back (unused again).
    Uses,
    /// Edits 0, 2, 4, …: one material's diffuse red set to 1.5 (an error: an albedo above 1,
    /// the material not lowered); 1, 3, 5, …: put back.
    BadValue,
    /// Edits 0, 2, 4, …: a material nothing names inserted after the first one (unused: a
    /// warning; every later material's table index moves up); 1, 3, 5, …: deleted.
    NewMaterial,
    /// Edits 0, 2, 4, …: `gloss` given an error (`+ #fff`: every material naming it fails
    /// quietly, not lowered); 1, 3, 5, …: taken out.
    LetError,
    /// The camera's eye moves along x.
    Camera,
    /// The light's intensity changes.
    Light,
    /// The render block's sample count changes (9, 4, 9, …).
    Render,
    /// The constant `lens`, which the camera's `fov` names, changes (the camera checked again).
    SettingLet,
    /// Edits 0, 2, 4, …: a stray `=` typed into `let gloss` (a syntax error that loses the
    /// constant all 100 materials name); 1, 3, 5, …: taken out.
    LetLost,
    /// Edits 0, 2, 4, …: a stray `=` typed into one material's line (a syntax error that loses
    /// a material 1,000 objects name; another material each pair); 1, 3, 5, …: taken out.
    MaterialLost,
    /// The group's transform changes (it is lifted).
    Group,
    /// Edits 0, 2, 4, …: material `m5` renamed `m5x` (its 1,000 objects now name an unknown
    /// material: errors, each with a did-you-mean); 1, 3, 5, …: named back.
    Rename,
    /// The OBJ mesh's file changes (`crate_a.obj`, `crate_b.obj` in turn: the build loads it).
    ObjMesh,
    /// The image texture's wrap mode changes.
    ImageTexture,
    /// The light is renamed (another name each time).
    LightRename,
    /// The camera is renamed (another name each time).
    CameraRename,
    /// Edits 0, 2, 4, …: a group line inserted after the other; 1, 3, 5, …: deleted.
    GroupAdded,
    /// Edits 0, 2, 4, …: material `m0` renamed `m0x` (the group and 1,000 objects name it:
    /// errors); 1, 3, 5, …: named back.
    GroupedRename,
    /// (Sixth session.) Edits 0, 2, 4, …: `let gloss` renamed `glossy` (the 100 materials that
    /// name it get an unknown-name error, not lowered); 1, 3, 5, …: named back.
    LetRenamed,
    /// Edits 0, 2, 4, …: a block of three declarations pasted after the first material (a
    /// texture, a material naming it, a mesh; all unused: warnings; every later material's
    /// table index moves); 1, 3, 5, …: the block deleted.
    Paste,
    /// The OBJ mesh's material override: `{ material "wood" mN }`, another material each time.
    Override,
    /// Edits 0, 2, 4, …: the group's object named a material not declared yet (an error);
    /// 1, 3, 5, …: that material's line added before the last `let` (the group resolves; the
    /// one it named before stays, unused).
    GroupNamesAdded,
    /// (Seventh session.) Edits 0, 2, 4, …: material `m5`'s line deleted (the 1,000 objects
    /// that name it get an unknown-name error with a did-you-mean); 1, 3, 5, …: put back.
    Removed,
    /// (Seventh session.) Edits 0, 2, 4, …: a material and two objects naming it pasted after
    /// the first material (every later material's table index moves); 1, 3, 5, …: deleted.
    PasteObjects,
    /// (Ninth session.) Edits 0, 2, 4, …: a second point light inserted before the last line;
    /// 1, 3, 5, …: deleted (the settings lowered again together; a full compile before).
    LightAdded,
    /// (Ninth session.) Edits 0, 2, 4, …: the light's intensity set to -1 (an error in a
    /// setting); 1, 3, 5, …: put back (full compiles before).
    SettingError,
    /// (Ninth session.) Edits 0, 2, 4, …: `let lens` (the camera's `fov` names it) renamed
    /// `lens2` (the camera gets an unknown-name error); 1, 3, 5, …: named back (full compiles
    /// before).
    LensRenamed,
    /// (Twelfth session.) Edits 0, 2, 4, …: a second `material m5` inserted after the last
    /// material (a duplicate-name error); 1, 3, 5, …: deleted (full compiles before).
    Redeclared,
    /// (Thirteenth session.) A second `let gloss` stands after the last material (a
    /// duplicate-name error: put in before the kind's edits and taken out after, neither
    /// measured); each edit changes the first `let gloss`'s value (the 100 materials that name
    /// it checked again, the second passed over; a full compile before). Every edit gives the
    /// error, so it runs in process only (`scnc watch` builds nothing while it stands).
    FirstEdited,
    /// (Fourteenth session.) Edits 0, 2, 4, …: `include "part_extra.scn"` (1,000 objects)
    /// inserted before the last line; 1, 3, 5, …: deleted (its statements added or removed as a
    /// block; a full compile before). One file only (`--split` cuts the parts at fixed lines).
    Include,
    /// (Fifteenth session.) Edits 0, 2, 4, …: an `object` line near the middle commented out
    /// (`// ` typed before it); 1, 3, 5, …: uncommented (a full compile before, the comment
    /// out: the region's parse did not arrive at the commented statement's start).
    CommentOut,
    /// (Fifteenth session.) Edits 0, 2, 4, …: the line of `material spare` (nothing names it)
    /// commented out; 1, 3, 5, …: uncommented (the same full compile before).
    CommentSpare,
    /// (Fifteenth session.) Edits 0, 2, 4, …: `let gloss` (its 100 materials name it)
    /// commented out (the materials get unknown-name errors); 1, 3, 5, …: uncommented (full
    /// compiles before).
    GlossCommented,
    /// (Seventeenth session.) `let unused = 0.5` stands right after `let gloss` (put in
    /// before the kind's edits and taken out after, neither measured); edits 0, 2, 4, …
    /// comment it out; 1, 3, 5, …: uncomment it (full compiles before: `let gloss`'s span
    /// took the comment).
    LetCommented,
    /// (Seventeenth session.) `include "part_extra.scn"` stands before the last line (put in
    /// before the kind's edits and taken out after, neither measured); each edit points it at
    /// the other of `part_extra.scn` and `part_other.scn` (1,000 objects each; a full compile
    /// before).
    IncludeRetarget,
    /// (Eighteenth session.) `include "part_other.scn"` stands before the last line (put in
    /// before the kind's edits and taken out after, neither measured); edits 0, 2, 4, …:
    /// `include "part_extra.scn"` (1,000 objects) inserted after the header, read before
    /// `part_other.scn` (whose file id then moves up); 1, 3, 5, …: deleted (its id moves back
    /// down). Full compiles before.
    IncludeFirst,
}

/// The line a kind's edits stand beside, put in before them and taken out after (neither
/// measured): its place in `lines` and its text.
fn standing(kind: Kind, lines: &[String]) -> Option<(usize, String)> {
    match kind {
        Kind::LetCommented => Some((LET_LINE + 1, LET_AFTER_LET.to_string())),
        Kind::IncludeRetarget => Some((lines.len() - 1, "include \"part_extra.scn\"".into())),
        Kind::IncludeFirst => Some((lines.len() - 1, "include \"part_other.scn\"".into())),
        _ => None,
    }
}

/// The line of [`Kind::LetCommented`]'s `let`, right after `let gloss`.
const LET_AFTER_LET: &str = "let unused = 0.5";

const KINDS: [Kind; 45] = [
    Kind::Object,
    Kind::Material,
    Kind::Let,
    Kind::Insert,
    Kind::Delete,
    Kind::UnusedLet,
    Kind::Uses,
    Kind::NewMaterial,
    Kind::Camera,
    Kind::Light,
    Kind::Render,
    Kind::SettingLet,
    Kind::Group,
    Kind::ObjMesh,
    Kind::ImageTexture,
    Kind::LightRename,
    Kind::CameraRename,
    Kind::GroupAdded,
    Kind::Paste,
    Kind::Override,
    Kind::PasteObjects,
    Kind::Include,
    // Last: each error is taken out again (an even number of edits).
    Kind::BadValue,
    Kind::LetError,
    Kind::Rename,
    Kind::Typo,
    Kind::Stray,
    Kind::Cut,
    Kind::LetLost,
    Kind::MaterialLost,
    Kind::GroupedRename,
    Kind::LetRenamed,
    Kind::Removed,
    Kind::LightAdded,
    Kind::SettingError,
    Kind::LensRenamed,
    Kind::Redeclared,
    Kind::FirstEdited,
    // Last: it leaves a material line per pair before the last `let`.
    Kind::GroupNamesAdded,
    Kind::CommentOut,
    Kind::CommentSpare,
    Kind::GlossCommented,
    Kind::LetCommented,
    Kind::IncludeRetarget,
    Kind::IncludeFirst,
];

/// Kinds whose even edits make an error (`scnc watch` builds nothing then: its figure is save →
/// the `error` event).
fn errs(kind: Kind) -> bool {
    matches!(
        kind,
        Kind::Typo
            | Kind::Stray
            | Kind::Cut
            | Kind::BadValue
            | Kind::LetError
            | Kind::LetLost
            | Kind::MaterialLost
            | Kind::Rename
            | Kind::GroupedRename
            | Kind::LetRenamed
            | Kind::GroupNamesAdded
            | Kind::Removed
            | Kind::SettingError
            | Kind::LensRenamed
            | Kind::Redeclared
            | Kind::GlossCommented
    )
}

/// Kinds that lower the scene settings again (every camera, light and render block: how many
/// statements that checks is not asserted, only that the edit is incremental).
fn settings(kind: Kind) -> bool {
    matches!(
        kind,
        Kind::Camera
            | Kind::Light
            | Kind::Render
            | Kind::SettingLet
            | Kind::LightRename
            | Kind::CameraRename
            | Kind::LightAdded
            | Kind::SettingError
            | Kind::LensRenamed
    )
}

/// Edit `k` of kind `kind` of `lines`. Returns the new text.
fn edit(lines: &mut Vec<String>, objects: usize, kind: Kind, k: usize) -> String {
    let middle = HEADER + objects / 2 + (k * 7919) % (objects / 4);
    match kind {
        Kind::Object => {
            let i = objects / 2 + (k * 7919) % (objects / 4);
            lines[HEADER + i] = object_line(i, 1 + k % 9);
        }
        Kind::Insert => lines.insert(middle, lines[middle].clone()),
        Kind::Delete => {
            lines.remove(middle);
        }
        Kind::UnusedLet if k.is_multiple_of(2) => {
            lines.insert(LET_LINE + 1, format!("let unused = 0.{}", k % 10));
        }
        Kind::UnusedLet => {
            lines.remove(LET_LINE + 1);
        }
        // The pair of edits 2j, 2j + 1 is of one line.
        Kind::Typo => {
            let i = HEADER + objects / 2 + (k / 2 * 7919) % (objects / 4);
            let (name, typo) = ("{ material m", "{ material mm");
            let (from, to) = if k.is_multiple_of(2) {
                (name, typo)
            } else {
                (typo, name)
            };
            lines[i] = lines[i].replacen(from, to, 1);
        }
        Kind::Uses => {
            let i = objects / 2 + (k / 2 * 7919) % (objects / 4);
            lines[HEADER + i] = if k.is_multiple_of(2) {
                let line = object_line(i, 0);
                let at = line.find("{ material m").unwrap_or(0) + "{ material ".len();
                let end = at + line[at..].find(' ').unwrap_or(0);
                format!("{}spare{}", &line[..at], &line[end..])
            } else {
                object_line(i, 0)
            };
        }
        Kind::NewMaterial if k.is_multiple_of(2) => {
            let line = format!(
                "material added{k} = phong {{ diffuse rgb(0.{}, 0.1, 0.1) }}",
                k % 10
            );
            lines.insert(FIRST_MATERIAL + 1, line);
        }
        Kind::NewMaterial => {
            lines.remove(FIRST_MATERIAL + 1);
        }
        Kind::BadValue => {
            let m = (k / 2 * 37) % 100;
            lines[FIRST_MATERIAL + m] = if k.is_multiple_of(2) {
                material_line(m, m % 10).replacen("rgb(0.", "rgb(1.5", 1)
            } else {
                material_line(m, m % 10)
            };
        }
        Kind::Stray | Kind::Cut => {
            let i = HEADER + objects / 2 + (k / 2 * 7919) % (objects / 4);
            if k.is_multiple_of(2) {
                let line = &mut lines[i];
                match kind {
                    Kind::Stray => *line = line.replacen("{ material", "{ material =", 1),
                    _ => line.truncate(line.find("translate").unwrap_or(line.len())),
                }
            } else {
                lines[i] = object_line(i - HEADER, 0);
            }
        }
        Kind::Material => {
            let m = (k * 37) % 100;
            lines[FIRST_MATERIAL + m] = material_line(m, (m + 1 + k % 9) % 10);
        }
        Kind::Let => lines[LET_LINE] = let_line(k + 1),
        Kind::LetError if k.is_multiple_of(2) => lines[LET_LINE] = let_line(k) + " + #fff",
        Kind::LetError => lines[LET_LINE] = let_line(k),
        Kind::Camera => lines[CAMERA_LINE] = camera_line(501 + k % 50),
        Kind::Light => {
            let last = lines.len() - 1;
            lines[last] = light_line(100_001 + k % 1000);
        }
        Kind::Render => lines[RENDER_LINE] = render_line([9, 4][k % 2]),
        Kind::SettingLet => {
            let at = lines.len() - 2;
            lines[at] = lens_line(k + 1);
        }
        Kind::LetLost if k.is_multiple_of(2) => {
            lines[LET_LINE] = lines[LET_LINE].replacen("gloss =", "gloss = =", 1);
        }
        Kind::LetLost => lines[LET_LINE] = lines[LET_LINE].replacen("= =", "=", 1),
        Kind::MaterialLost => {
            let m = (k / 2 * 37) % 100;
            lines[FIRST_MATERIAL + m] = if k.is_multiple_of(2) {
                material_line(m, m % 10).replacen("= phong", "= = phong", 1)
            } else {
                material_line(m, m % 10)
            };
        }
        Kind::Group => lines[GROUP_LINE] = group_line(1 + k % 9),
        Kind::ObjMesh => lines[OBJ_LINE] = obj_line(k + 1),
        Kind::ImageTexture => lines[IMAGE_LINE] = image_line(k + 1),
        Kind::LightRename => {
            let last = lines.len() - 1;
            let name = lines[last].split(' ').nth(1).unwrap_or("sun").to_string();
            lines[last] = lines[last].replacen(&name, &format!("sun{k}"), 1);
        }
        Kind::CameraRename => {
            let name = lines[CAMERA_LINE]
                .split(' ')
                .nth(1)
                .unwrap_or("main")
                .to_string();
            lines[CAMERA_LINE] = lines[CAMERA_LINE].replacen(&name, &format!("main{k}"), 1);
        }
        Kind::GroupAdded if k.is_multiple_of(2) => {
            lines.insert(GROUP_LINE + 1, added_group_line(k))
        }
        Kind::GroupAdded => {
            lines.remove(GROUP_LINE + 1);
        }
        Kind::GroupedRename => {
            let (name, renamed) = ("material m0 =", "material m0x =");
            let (from, to) = if k.is_multiple_of(2) {
                (name, renamed)
            } else {
                (renamed, name)
            };
            let line = &mut lines[FIRST_MATERIAL];
            *line = line.replacen(from, to, 1);
        }
        Kind::LetRenamed => {
            let (from, to) = match k % 2 {
                0 => ("let gloss =", "let glossy ="),
                _ => ("let glossy =", "let gloss ="),
            };
            lines[LET_LINE] = lines[LET_LINE].replacen(from, to, 1);
        }
        Kind::Paste if k.is_multiple_of(2) => {
            let block = [
                format!("texture pasted{k} = checker {{ even #fff  odd #000 }}"),
                format!("material pasted{k} = phong {{ diffuse pasted{k} }}"),
                format!("mesh pasted{k} = box {{ size 1 }}"),
            ];
            let at = FIRST_MATERIAL + 1;
            lines.splice(at..at, block);
        }
        Kind::Paste => {
            lines.drain(FIRST_MATERIAL + 1..FIRST_MATERIAL + 4);
        }
        Kind::Override => {
            let base = lines[OBJ_LINE].split(" {").next().unwrap_or("").to_string();
            lines[OBJ_LINE] = format!("{base} {{ material \"wood\" m{} }}", 1 + k % 99);
        }
        Kind::GroupNamesAdded if k.is_multiple_of(2) => {
            let named = format!("material later{k} ");
            lines[GROUP_LINE] = group_line(0).replacen("material m0 ", &named, 1);
        }
        Kind::GroupNamesAdded => {
            let at = lines.len() - 2;
            let line = format!("material later{} = phong {{ diffuse #345 }}", k - 1);
            lines.insert(at, line);
        }
        Kind::Removed if k.is_multiple_of(2) => {
            lines.remove(FIRST_MATERIAL + 5);
        }
        Kind::Removed => lines.insert(FIRST_MATERIAL + 5, material_line(5, 5)),
        Kind::PasteObjects if k.is_multiple_of(2) => {
            let block = [
                format!("material pasted{k} = phong {{ diffuse #345 }}"),
                format!("object tree {{ material pasted{k} }}"),
                format!(
                    "object rock {{ material pasted{k}  transform {{ translate ({k}, 0, 1) }} }}"
                ),
            ];
            let at = FIRST_MATERIAL + 1;
            lines.splice(at..at, block);
        }
        Kind::PasteObjects => {
            lines.drain(FIRST_MATERIAL + 1..FIRST_MATERIAL + 4);
        }
        Kind::LightAdded if k.is_multiple_of(2) => {
            let at = lines.len() - 1;
            let line = format!("light lamp = point {{ position (300, 50, {k})  intensity 900 }}");
            lines.insert(at, line);
        }
        Kind::LightAdded => {
            let at = lines.len() - 2;
            lines.remove(at);
        }
        Kind::SettingError => {
            let last = lines.len() - 1;
            let name = lines[last].split(' ').nth(1).unwrap_or("sun").to_string();
            let intensity = if k.is_multiple_of(2) { "-1" } else { "100000" };
            lines[last] = light_line(0).replacen("sun", &name, 1).replacen(
                "intensity 0",
                &format!("intensity {intensity}"),
                1,
            );
        }
        Kind::Include if k.is_multiple_of(2) => {
            let at = lines.len() - 1;
            lines.insert(at, "include \"part_extra.scn\"".to_string());
        }
        Kind::Include => {
            let at = lines.len() - 2;
            lines.remove(at);
        }
        Kind::IncludeFirst if k.is_multiple_of(2) => {
            lines.insert(1, "include \"part_extra.scn\"".to_string());
        }
        Kind::IncludeFirst => {
            lines.remove(1);
        }
        Kind::Redeclared if k.is_multiple_of(2) => {
            let line = format!(
                "material m5 = phong {{ diffuse rgb(0.{}, 0.1, 0.1) }}",
                k % 10
            );
            lines.insert(FIRST_MATERIAL + 100, line);
        }
        Kind::Redeclared => {
            lines.remove(FIRST_MATERIAL + 100);
        }
        Kind::FirstEdited => lines[LET_LINE] = let_line(1 + k % 89),
        Kind::IncludeRetarget => {
            let at = lines.len() - 2;
            lines[at] = match lines[at].contains("part_extra") {
                true => "include \"part_other.scn\"".into(),
                false => "include \"part_extra.scn\"".into(),
            };
        }
        Kind::CommentOut | Kind::CommentSpare | Kind::GlossCommented | Kind::LetCommented => {
            let at = match kind {
                Kind::CommentOut => HEADER + objects / 2 + (k / 2 * 7919) % (objects / 4),
                Kind::GlossCommented => LET_LINE,
                Kind::LetCommented => LET_LINE + 1,
                _ => FIRST_MATERIAL + 100,
            };
            lines[at] = match lines[at].strip_prefix("// ") {
                Some(line) => line.to_string(),
                None => format!("// {}", lines[at]),
            };
        }
        Kind::LensRenamed => {
            let at = lines.len() - 2;
            let (from, to) = match k % 2 {
                0 => ("let lens =", "let lens2 ="),
                _ => ("let lens2 =", "let lens ="),
            };
            lines[at] = lines[at].replacen(from, to, 1);
        }
        Kind::Rename => {
            let (name, renamed) = ("material m5 =", "material m5x =");
            let (from, to) = if k.is_multiple_of(2) {
                (name, renamed)
            } else {
                (renamed, name)
            };
            let line = &mut lines[FIRST_MATERIAL + 5];
            *line = line.replacen(from, to, 1);
        }
    }
    let mut text = lines.join("\n");
    text.push('\n');
    text
}

/// The statements edit `k` of `kind` checks again: the edited one, for the constant every
/// material (which names it), none for a deleted line.
fn checked(kind: Kind, k: usize) -> usize {
    match kind {
        Kind::Let => 101,
        Kind::SettingLet => 2,
        Kind::UnusedLet | Kind::NewMaterial | Kind::GroupAdded => 1 - k % 2,
        Kind::Paste | Kind::PasteObjects => 3 * (1 - k % 2),
        // The file's header and objects and the include; removed, none.
        Kind::Include | Kind::IncludeFirst => (EXTRA_OBJECTS + 2) * (1 - k % 2),
        Kind::Delete => 0,
        Kind::CommentOut | Kind::CommentSpare | Kind::LetCommented => k % 2,
        // The old file's objects cut out (not counted), the new file's header, objects and
        // include checked.
        Kind::IncludeRetarget => EXTRA_OBJECTS + 2,
        _ => 1,
    }
}

/// Whether `--only KIND,KIND` (kinds by name) lets `kind` run: all when not given.
fn only(kind: Kind) -> bool {
    let args: Vec<String> = std::env::args().collect();
    let at = args.iter().position(|a| a == "--only");
    let names = at.and_then(|i| args.get(i + 1));
    names.is_none_or(|n| n.split(',').any(|n| n == format!("{kind:?}")))
}

/// `--split N`: the scene's objects split over `N` included files (0: one file).
fn parts() -> usize {
    let args: Vec<String> = std::env::args().collect();
    let at = args.iter().position(|a| a == "--split");
    at.and_then(|i| args.get(i + 1)?.parse().ok()).unwrap_or(0)
}

/// Whether `kind` keeps the scene's lines in place: the kinds `--split` runs (an edit of
/// included files' text is cut at fixed object lines). A syntax error in an object line of an
/// included file is answered from the memo (seventh session); one that loses a declaration
/// (`LetLost`, `MaterialLost`) is a full compile in a scene with includes.
fn splits(kind: Kind) -> bool {
    !matches!(
        kind,
        Kind::Insert
            | Kind::Delete
            | Kind::UnusedLet
            | Kind::NewMaterial
            | Kind::GroupAdded
            | Kind::LetLost
            | Kind::MaterialLost
            | Kind::Removed
            | Kind::PasteObjects
            | Kind::Redeclared
            | Kind::FirstEdited
            | Kind::Include
            | Kind::LetCommented
            | Kind::IncludeRetarget
            | Kind::IncludeFirst
    )
}

/// The scene file `text` (the lines of [`scene`], edited) as the files `scnc` reads:
/// `big.scn` alone, or with `parts` > 0 the root `big.scn` (declarations, settings, one
/// `include "partP.scn"` per part where the objects stood) and the parts, each a run of the
/// objects (generated scenes are often written a block per file).
fn files_of(text: &str, objects: usize, parts: usize) -> Vec<(String, String)> {
    if parts == 0 {
        return vec![("big.scn".to_string(), text.to_string())];
    }
    let lines: Vec<&str> = text.lines().collect();
    let chunk = objects.div_ceil(parts);
    let mut root: Vec<String> = lines[..HEADER].iter().map(|l| l.to_string()).collect();
    let mut files = vec![("big.scn".to_string(), String::new())];
    for p in 0..parts {
        let (from, to) = ((p * chunk).min(objects), ((p + 1) * chunk).min(objects));
        root.push(format!("include \"part{p}.scn\""));
        let mut part = String::from("scnc 1\n");
        for line in &lines[HEADER + from..HEADER + to] {
            part.push_str(line);
            part.push('\n');
        }
        files.push((format!("part{p}.scn"), part));
    }
    root.extend(lines[HEADER + objects..].iter().map(|l| l.to_string()));
    files[0].1 = root.join("\n") + "\n";
    files
}

/// A loader serving the scene's `files` ([`files_of`]) and assets.
fn loader_with(files: &[(String, String)], assets: &[(&str, Vec<u8>)]) -> MemLoader {
    let mut loader = MemLoader::new();
    for (name, text) in files {
        loader.insert(name.as_str(), text.as_str());
    }
    for (name, bytes) in assets {
        loader.insert(*name, bytes.clone());
    }
    loader
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn max(v: &[f64]) -> f64 {
    v.iter().copied().fold(0.0, f64::max)
}

fn front_end(objects: usize, edits: usize) {
    let mut lines = scene(objects);
    let original = lines.join("\n") + "\n";
    let parts = parts();
    let files = |text: &str| files_of(text, objects, parts);
    let path = Path::new("big.scn");
    let overrides = Overrides::default();
    let assets = assets();
    let mut full = Vec::new();
    for _ in 0..3 {
        let loader = loader_with(&files(&original), &assets);
        let t = Instant::now();
        let r = compile_with(path, &loader, &mut SourceMap::new(), &overrides);
        full.push(t.elapsed().as_secs_f64() * 1e3);
        assert!(r.value.is_some(), "the scene compiles");
    }
    let loader = loader_with(&files(&original), &assets);
    // The memo's own heap: what the incremental front end keeps between compiles (the text,
    // statement spans, constants, name tables, per-statement records, diagnostics and the IR),
    // measured with the compile's result dropped; and the peak while it compiles the first time.
    let base = CURRENT.load(Ordering::Relaxed);
    PEAK.store(base, Ordering::Relaxed);
    let mut inc = Incremental::new(overrides.clone());
    let t = Instant::now();
    let r = inc.compile(path, &loader, &mut SourceMap::new());
    let first = t.elapsed().as_secs_f64() * 1e3;
    drop(r);
    let (memo, peak) = (
        CURRENT.load(Ordering::Relaxed).saturating_sub(base),
        PEAK.load(Ordering::Relaxed) - base,
    );
    println!(
        "incremental memo after the first compile: {:.1} MB = {:.2} x source; peak during it \
         {:.1} MB = {:.2} x source",
        memo as f64 / 1e6,
        memo as f64 / original.len() as f64,
        peak as f64 / 1e6,
        peak as f64 / original.len() as f64
    );
    let mut cache = BuildCache::new();
    let opts = BuildOptions::default();
    println!(
        "front end, {} bytes in {} file(s): full compile median {:.1} ms; incremental: first \
         (full, with memo) {first:.1} ms",
        original.len(),
        parts + 1,
        median(&mut full),
    );
    let run = |k: Kind| only(k) && (parts == 0 || splits(k));
    for kind in KINDS.into_iter().filter(|&k| run(k)) {
        let mut times = Vec::new();
        let mut build: [Vec<f64>; 3] = Default::default();
        // Pairs of edits for the errors, so that each is taken out before the next kind (and
        // for an inserted material, which would move the material lines of the next kinds).
        let paired = errs(kind)
            || matches!(
                kind,
                Kind::NewMaterial
                    | Kind::GroupAdded
                    | Kind::Paste
                    | Kind::PasteObjects
                    | Kind::Include
                    | Kind::IncludeFirst
            );
        let count = if paired { edits + edits % 2 } else { edits };
        // A full compile of the first error, for comparison.
        let mut full_error = None;
        // What `scnc watch`'s `error` event of each error costs to make ([`error_event_costs`]).
        let mut event_parts: Vec<([f64; 4], usize)> = Vec::new();
        // The incremental compiles' CPU time (ms), beside their wall time.
        let mut cpu_times = Vec::new();
        // The second `let gloss` the kind's edits stand beside (its error: no value).
        let dup = FIRST_MATERIAL + 100;
        if kind == Kind::FirstEdited {
            lines.insert(dup, "let gloss = 0.5".to_string());
            let text = lines.join("\n") + "\n";
            let loader = loader_with(&files(&text), &assets);
            let r = inc.compile(path, &loader, &mut SourceMap::new());
            assert!(r.value.is_none(), "a duplicate-name error");
        }
        let stands = standing(kind, &lines);
        if let Some((at, line)) = &stands {
            lines.insert(*at, line.clone());
            let text = lines.join("\n") + "\n";
            let loader = loader_with(&files(&text), &assets);
            let r = inc.compile(path, &loader, &mut SourceMap::new());
            assert!(r.value.is_some(), "the line put in compiles");
        }
        for k in 0..count {
            let text = edit(&mut lines, objects, kind, k);
            let loader = loader_with(&files(&text), &assets);
            if (errs(kind) || kind == Kind::FirstEdited) && k == 0 {
                let t = Instant::now();
                let r = compile_with(path, &loader, &mut SourceMap::new(), &overrides);
                full_error = Some((t.elapsed().as_secs_f64() * 1e3, r.diagnostics.len()));
            }
            let t = Instant::now();
            let cpu = cpu_time::ThreadTime::now();
            let mut sources = SourceMap::new();
            let r = inc.compile(path, &loader, &mut sources);
            times.push(t.elapsed().as_secs_f64() * 1e3);
            cpu_times.push(cpu.elapsed().as_secs_f64() * 1e3);
            if kind == Kind::FirstEdited {
                // The `let` and the 100 materials that name it; not the second `let`.
                assert!(r.value.is_none(), "{kind:?} edit {k}: the error stands");
                let fast = matches!(inc.reuse, Reuse::Statements { checked: 101, .. });
                assert!(fast, "{kind:?} edit {k} took {:?}", inc.reuse);
                continue;
            }
            if errs(kind) && k % 2 == 0 {
                event_parts.push(error_event_costs(&r.diagnostics, &sources));
            }
            if errs(kind) {
                assert_eq!(r.value.is_none(), k % 2 == 0, "{kind:?} edit {k}: an error");
                // A syntax error is answered from the memo of the text before it (nothing
                // checked); taking it out gives that text again (`Unchanged`) or another value.
                let checks = matches!(
                    kind,
                    Kind::Typo
                        | Kind::BadValue
                        | Kind::LetError
                        | Kind::Rename
                        | Kind::GroupedRename
                        | Kind::LetRenamed
                        | Kind::GroupNamesAdded
                        | Kind::Removed
                        | Kind::Redeclared
                        | Kind::GlossCommented
                );
                let checked = match kind {
                    // The 100 materials that name `gloss`; put back, the `let` too.
                    Kind::GlossCommented => 100 + k % 2,
                    Kind::LetError => checked(Kind::Let, k),
                    // The material and the objects that name `m5` (or `m5x`), counted in the
                    // text: the `Insert` and `Delete` kinds before it leave other lines in the
                    // middle than the scene began with (one object naming `m5` fewer).
                    Kind::Rename => lines_naming(&text, &["m5", "m5x"]),
                    // The objects that name `m5`; put back, the material too.
                    Kind::Removed => lines_naming(&text, &["m5"]),
                    // The material, the objects that name `m0` and the group.
                    Kind::GroupedRename => 2 + objects.div_ceil(100),
                    // The `let` and the 100 materials that name it.
                    Kind::LetRenamed => 101,
                    // The group; then the material added and the group.
                    Kind::GroupNamesAdded => 1 + k % 2,
                    // The duplicate added (its error made); removed, nothing.
                    Kind::Redeclared => 1 - k % 2,
                    _ => usize::from(checks || k % 2 == 1),
                };
                let unchanged = !checks && inc.reuse == Reuse::Unchanged;
                let incremental = matches!(inc.reuse, Reuse::Statements { .. });
                assert!(
                    unchanged
                        || (settings(kind) && incremental)
                        || matches!(inc.reuse, Reuse::Statements { checked: n, .. } if n == checked),
                    "{kind:?} edit {k} took {:?}",
                    inc.reuse
                );
                continue;
            }
            let desc = r.value.expect("the edit compiles");
            let built = scene::build_cached(&desc, &loader, &opts, &mut cache)
                .value
                .expect("the edit builds");
            let t = &built.timings;
            for (v, d) in build.iter_mut().zip([t.total, t.asset_load, t.accel_build]) {
                v.push(d.as_secs_f64() * 1e3);
            }
            cache.recycle(built);
            let incremental = matches!(inc.reuse, Reuse::Statements { .. });
            assert!(
                (settings(kind) && incremental)
                    || matches!(inc.reuse, Reuse::Statements { checked: n, .. } if n == checked(kind, k)),
                "{kind:?} edit {k} took {:?}",
                inc.reuse
            );
        }
        if kind == Kind::FirstEdited {
            println!(
                "{kind:?} edits ({count}, a duplicate-name error standing): incremental compile \
                 median {:.1} ms (slowest {:.1} ms), CPU {:.1} ms; a full compile of the first \
                 (ms, diagnostics) {full_error:?}",
                median(&mut times.clone()),
                max(&times),
                median(&mut cpu_times)
            );
            lines.remove(dup);
            let text = lines.join("\n") + "\n";
            let loader = loader_with(&files(&text), &assets);
            let r = inc.compile(path, &loader, &mut SourceMap::new());
            assert!(r.value.is_some(), "the duplicate taken out");
            continue;
        }
        if let Some((at, _)) = stands {
            lines.remove(at);
            let text = lines.join("\n") + "\n";
            let loader = loader_with(&files(&text), &assets);
            let r = inc.compile(path, &loader, &mut SourceMap::new());
            assert!(r.value.is_some(), "the line taken out");
        }
        let [mut total, mut assets, mut accel] = build;
        if errs(kind) {
            let errors: Vec<f64> = times.iter().copied().step_by(2).collect();
            let mut error_cpu: Vec<f64> = cpu_times.iter().copied().step_by(2).collect();
            let fixes: Vec<f64> = times.iter().copied().skip(1).step_by(2).collect();
            println!(
                "{kind:?} edits ({count}, every other one an error): incremental compile median \
                 {:.1} ms (slowest {:.1} ms); the errors {:.1} ms (slowest {:.1}), the edits \
                 taking them out {:.1} ms (slowest {:.1}); a full compile of the first error \
                 (ms, diagnostics) {full_error:?}",
                median(&mut times.clone()),
                max(&times),
                median(&mut errors.clone()),
                max(&errors),
                median(&mut fixes.clone()),
                max(&fixes)
            );
            let part =
                |i: usize| median(&mut event_parts.iter().map(|p| p.0[i]).collect::<Vec<_>>());
            println!(
                "  the errors' CPU time {:.1} ms (median); the error event ({} bytes), CPU time \
                 medians: made as a value {:.1} ms, printed {:.1} ms, plain text {:.1} ms; \
                 written straight (this session, text included) {:.1} ms",
                median(&mut error_cpu),
                event_parts.first().map_or(0, |p| p.1),
                part(0),
                part(2),
                part(1),
                part(3)
            );
            continue;
        }
        println!(
            "{kind:?} edits ({edits}): incremental compile median {:.1} ms (slowest {:.1} ms); \
             scene::build_cached after each: median {:.1} ms (meshes and checks {:.1} ms, \
             acceleration structure {:.1} ms)",
            median(&mut times.clone()),
            max(&times),
            median(&mut total),
            median(&mut assets),
            median(&mut accel)
        );
    }
}

/// What `scnc watch` does to send the `error` event of `diags` (`cli/watch/status.rs`), in ms
/// of this thread's CPU time (the machine is shared): the fifth session's way, the diagnostics as a JSON value (0) printed in the event
/// (2); their plain text, 100 columns (1); and this session's way, the whole line written
/// straight from the diagnostics, text included (3); with the line's length in bytes (both
/// ways give the same bytes: asserted).
fn error_event_costs(diags: &[scnc::diag::Diagnostic], sources: &SourceMap) -> ([f64; 4], usize) {
    // The line indices are made by the first of the two; made here, neither pays them.
    for (id, _) in sources.files() {
        sources.line_col(id, 0);
    }
    let t = cpu_time::ThreadTime::now();
    let json = scnc::diag::json_diagnostics(diags, sources);
    let t_json = t.elapsed();
    let text = scnc::diag::render_plain_all(diags, sources, 100);
    let t_text = t.elapsed();
    let line = serde_json::json!({"event": "error", "diagnostics": json, "text": text}).to_string();
    let t_value = t.elapsed();
    let t = cpu_time::ThreadTime::now();
    let text = scnc::diag::render_plain_all(diags, sources, 100);
    let mut direct = Vec::new();
    direct.extend_from_slice(br#"{"diagnostics":"#);
    scnc::diag::write_json_diagnostics(&mut direct, diags, sources);
    direct.extend_from_slice(br#","event":"error","text":"#);
    serde_json::to_writer(&mut direct, &text).expect("a string serialises");
    direct.push(b'}');
    let t_direct = t.elapsed();
    if scnc::diag::maps_sort_keys() {
        assert_eq!(
            direct,
            line.as_bytes(),
            "the event written directly is the value printed"
        );
    }
    let ms = |d: Duration| d.as_secs_f64() * 1e3;
    let parts = [
        ms(t_json),
        ms(t_text - t_json),
        ms(t_value - t_text),
        ms(t_direct),
    ];
    (parts, line.len())
}

/// How the bench saves the scene file in `scnc watch`'s part.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Save {
    /// Written beside it, then renamed into place (as vim and many IDEs save): the watcher
    /// sees the file whole, at once.
    Rename,
    /// `fs::write` in place (`--in-place`: truncated, then written, as many other editors and
    /// scripts save): the watcher sees it modified while it is written, and must wait for the
    /// writer to finish (on Linux, its close) not to read it half-written (docs/watch.md).
    InPlace,
}

/// Saves `text` to `scn` the `how` way.
fn save(scn: &Path, text: &str, how: Save) {
    match how {
        Save::Rename => {
            let tmp = scn.with_extension("scn.saving");
            std::fs::write(&tmp, text).expect("save");
            std::fs::rename(&tmp, scn).expect("save: rename into place");
        }
        Save::InPlace => std::fs::write(scn, text).expect("save in place"),
    }
}

fn watch(objects: usize, edits: usize, how: Save) {
    let mut lines = scene(objects);
    let original = lines.join("\n") + "\n";
    let dir = std::env::temp_dir().join(format!("scnc-incr-bench-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    let parts = parts();
    let mut saved = files_of(&original, objects, parts);
    for (name, text) in &saved {
        std::fs::write(dir.join(name), text).expect("write scene");
    }
    // Saves the files of the scene `text` that changed (an editor saves the file edited).
    let mut save_all = |text: &str| {
        let files = files_of(text, objects, parts);
        for ((name, text), (_, old)) in files.iter().zip(&saved) {
            if text != old {
                save(&dir.join(name), text, how);
            }
        }
        saved = files;
    };
    for (name, bytes) in assets() {
        std::fs::write(dir.join(name), bytes).expect("write an asset");
    }
    let watch = WatchProcess::start(&dir, "big.scn", Duration::from_secs(120));
    let wait = |name: &str, final_only: bool| watch.wait(name, final_only);
    let (_, first) = wait("compiled", false);
    wait("pass", true);
    println!(
        "scnc watch (saves: {how:?}), first compile {:.0} ms + build {:.0} ms",
        first["compile_ms"].as_f64().unwrap_or(0.0),
        first["build_ms"].as_f64().unwrap_or(0.0),
    );
    let run = |k: Kind| only(k) && (parts == 0 || splits(k));
    let run = |k: Kind| run(k) && k != Kind::FirstEdited;
    for kind in KINDS.into_iter().filter(|&k| !errs(k) && run(k)) {
        let mut figures: [Vec<f64>; 6] = Default::default();
        let mut incremental = 0;
        // What the cached builds made again (`rebuilt` of the `compiled` events), all edits.
        let mut rebuilt = std::collections::BTreeSet::new();
        let stands = standing(kind, &lines);
        if let Some((at, line)) = &stands {
            lines.insert(*at, line.clone());
            save_all(&(lines.join("\n") + "\n"));
            wait("compiled", false);
            wait("pass", true);
        }
        for k in 0..edits {
            let text = edit(&mut lines, objects, kind, 1000 + k);
            let t0 = Instant::now();
            save_all(&text);
            let (t1, _) = wait("checked", false);
            let (t3, c) = wait("compiled", false);
            let (t2, p) = wait("pass", false);
            incremental += usize::from(c["incremental"] == true);
            let made = c["rebuilt"].as_array().into_iter().flatten();
            rebuilt.extend(made.filter_map(|r| r.as_str().map(str::to_string)));
            let f = [
                (t1 - t0).as_secs_f64() * 1e3,
                (t2 - t0).as_secs_f64() * 1e3,
                c["compile_ms"].as_f64().unwrap_or(0.0),
                c["build_ms"].as_f64().unwrap_or(0.0),
                p["ms"].as_f64().unwrap_or(0.0),
                (t3 - t0).as_secs_f64() * 1e3,
            ];
            for (v, x) in figures.iter_mut().zip(f) {
                v.push(x);
            }
            wait("pass", true);
        }
        let [mut diag, mut image, mut compile, mut build, mut pass, mut built] = figures;
        println!(
            "  {kind:?} edits ({edits}, {incremental} incremental): save -> diagnostics \
             (checked event) median {:.1} ms (slowest {:.1}), save -> build done (compiled \
             event) median {:.1} ms, save -> first image median {:.1} ms (slowest {:.1}); of \
             which compile {:.1} ms, build {:.1} ms, first pass (1 spp, 640x360) {:.1} ms; \
             rebuilt {rebuilt:?}",
            median(&mut diag),
            max(&diag),
            median(&mut built),
            median(&mut image),
            max(&image),
            median(&mut compile),
            median(&mut build),
            median(&mut pass)
        );
        if let Some((at, _)) = stands {
            lines.remove(at);
            save_all(&(lines.join("\n") + "\n"));
            wait("compiled", false);
            wait("pass", true);
        }
    }
    // The errors, each then taken out: save -> the `error` event (the diagnostics; nothing is
    // built) and, for the edit taking it out, save -> `checked`, and the first pass after it.
    for kind in KINDS.into_iter().filter(|&k| errs(k) && run(k)) {
        let mut figures: [Vec<f64>; 3] = Default::default();
        // The watch loop's CPU time per error (ms): the save to the `watching` event after it.
        let mut cpu = Vec::new();
        for k in 0..edits + edits % 2 {
            let text = edit(&mut lines, objects, kind, 1000 + k);
            let cpu0 = watch.main_thread_cpu_ns();
            let t0 = Instant::now();
            save_all(&text);
            if k.is_multiple_of(2) {
                let (t1, _) = wait("error", false);
                figures[0].push((t1 - t0).as_secs_f64() * 1e3);
                wait("watching", false);
                cpu.push((watch.main_thread_cpu_ns() - cpu0) as f64 / 1e6);
                continue;
            }
            let (t1, _) = wait("checked", false);
            let (t2, _) = wait("pass", false);
            figures[1].push((t1 - t0).as_secs_f64() * 1e3);
            figures[2].push((t2 - t0).as_secs_f64() * 1e3);
            wait("pass", true);
        }
        let [mut error, mut fixed, mut image] = figures;
        println!(
            "  {kind:?} edits ({}, every other one an error): save -> diagnostics (error event) \
             median {:.1} ms (slowest {:.1}; the watch loop's CPU time {:.1} ms); taken out: \
             save -> checked median {:.1} ms (slowest {:.1}), save -> first image median {:.1} \
             ms (slowest {:.1})",
            edits + edits % 2,
            median(&mut error),
            max(&error),
            median(&mut cpu),
            median(&mut fixed),
            max(&fixed),
            median(&mut image),
            max(&image)
        );
    }
    drop(watch);
    let _ = std::fs::remove_dir_all(&dir);
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    let arg = |name: &str, default: usize| {
        args.iter()
            .position(|a| a == name)
            .and_then(|i| args.get(i + 1))
            .and_then(|v| v.parse().ok())
            .unwrap_or(default)
    };
    // Even: a kind's edits alternate between two texts (a declaration added, then taken out),
    // so an even count leaves the scene as the kind found it; with an odd one the next kind
    // ran on the last kind's edit (a group left added) and failed.
    let edits = arg("--edits", 16).next_multiple_of(2);
    let objects = arg("--objects", 100_000);
    front_end(objects, edits);
    let how = if args.iter().any(|a| a == "--in-place") {
        Save::InPlace
    } else {
        Save::Rename
    };
    if !args.iter().any(|a| a == "--no-watch") {
        watch(objects, edits, how);
    }
}
