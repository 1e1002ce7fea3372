//! The registry of diagnostic codes (`scnc::diag::Code`) against what the stages emit, both
//! ways: a code emitted but missing from the registry cannot compile (the code is an enum);
//! a registered code that nothing emits fails [`every_registered_code_is_emitted`], which
//! triggers every code from a bad scene, an explanation's example, an asset or the CLI.
//! And every explanation's example does what it says: the mistake emits its code, the fix
//! does not.

use std::collections::BTreeSet;
use std::io::Cursor;
use std::path::Path;
use std::process::Command;

use scnc::assets::{FsLoader, Loader, MemLoader};
use scnc::compile::{compile_file, compile_source, Compiled};
use scnc::diag::Code;
use scnc::film::Film;
use scnc::scene::{self, BuildOptions};

/// Codes no test can trigger, each with the reason. A code listed here that becomes
/// triggerable fails the test, so the list only shrinks.
const UNTRIGGERABLE: &[(Code, &str)] = &[
    (
        Code::BuildIndexOutOfRange,
        "defence in depth: the checker (inline meshes) and the OBJ parser reject bad indices first",
    ),
    (
        Code::ObjTooLarge,
        "needs an OBJ with more than 2^31 vertices",
    ),
    (
        Code::WriteEncode,
        "needs the image encoder to fail on a valid film",
    ),
];

const BASE: &str = "scnc 1
camera main { eye (0, 1, -5)  target (0, 1, 0)  fov 40deg }
material grey = phong { diffuse 0.5 }
mesh ball = sphere { radius 1 }
object ball { material grey }
";

fn codes_of(compiled: &Compiled) -> impl Iterator<Item = Code> + '_ {
    compiled.diagnostics.iter().map(|d| d.code)
}

/// Compiles `scn` and, when it compiles, builds it: every code of both stages.
fn build_codes(scn: &str, loader: &dyn Loader, options: &BuildOptions) -> Vec<Code> {
    let compiled = compile_source("scene.scn", scn, loader);
    let mut codes: Vec<Code> = codes_of(&compiled).collect();
    if let Some(desc) = &compiled.scene {
        let built = scene::build(desc, loader, options);
        codes.extend(built.diagnostics.iter().map(|d| d.code));
    }
    codes
}

fn mem(files: &[(&str, Vec<u8>)]) -> MemLoader {
    let mut loader = MemLoader::new();
    for (path, bytes) in files {
        loader.insert(*path, bytes.clone());
    }
    loader
}

/// The ```scn block after `label` ("Mistake" or "Fix") in an explanation.
fn example<'a>(explanation: &'a str, label: &str) -> Option<&'a str> {
    let after = &explanation[explanation.find(&format!("\n{label}"))?..];
    let start = after.find("```scn\n")? + "```scn\n".len();
    let len = after[start..].find("```")?;
    Some(&after[start..start + len])
}

/// The stages whose examples are whole scenes that show the mistake from source alone.
fn from_source(code: Code) -> bool {
    matches!(code.stage(), "syntax" | "include" | "check")
}

fn example_loader() -> MemLoader {
    mem(&[("common.scn", b"scnc 1\n".to_vec())])
}

#[test]
fn every_explanation_example_shows_its_code() {
    let loader = example_loader();
    let mut wrong = Vec::new();
    for &code in Code::ALL.iter().filter(|c| from_source(**c)) {
        let (Some(mistake), Some(fix)) = (
            example(code.explanation(), "Mistake"),
            example(code.explanation(), "Fix"),
        ) else {
            if code != Code::IncludeTooDeep {
                wrong.push(format!("{code}: no ```scn mistake and fix"));
            }
            continue;
        };
        let emitted: Vec<Code> = codes_of(&compile_source("scene.scn", mistake, &loader)).collect();
        if !emitted.contains(&code) {
            wrong.push(format!("{code}: the mistake emits {emitted:?}"));
        }
        let emitted: Vec<Code> = codes_of(&compile_source("scene.scn", fix, &loader)).collect();
        if emitted.contains(&code) {
            wrong.push(format!("{code}: the fix still emits it"));
        }
    }
    assert!(wrong.is_empty(), "{wrong:#?}");
}

/// Build-stage codes whose examples are whole scenes that need no files.
const SELF_CONTAINED_BUILD: [Code; 5] = [
    Code::BuildDegenerateMesh,
    Code::BuildDegenerateTriangles,
    Code::BuildSingularTransform,
    Code::BuildLightFacesAway,
    Code::BuildPrecisionLost,
];

/// Build-stage codes whose examples need no files: built, the mistake shows its code and the
/// fix does not.
#[test]
fn self_contained_build_examples_show_their_code() {
    let loader = MemLoader::new();
    let opts = BuildOptions::default();
    for code in SELF_CONTAINED_BUILD {
        let mistake = example(code.explanation(), "Mistake").expect("a ```scn mistake");
        let fix = example(code.explanation(), "Fix").expect("a ```scn fix");
        let emitted = build_codes(mistake, &loader, &opts);
        assert!(
            emitted.contains(&code),
            "{code}: the mistake emits {emitted:?}"
        );
        let emitted = build_codes(fix, &loader, &opts);
        assert!(
            !emitted.contains(&code),
            "{code}: the fix emits {emitted:?}"
        );
    }
}

#[test]
fn every_registered_code_is_emitted() {
    let mut emitted = BTreeSet::new();
    emitted.extend(bad_scene_codes());
    emitted.extend(example_codes());
    emitted.extend(include_chain_codes());
    emitted.extend(build_stage_codes());
    emitted.extend(obj_codes());
    emitted.extend(write_codes());
    emitted.extend(cli_codes());
    emitted.extend(tile_codes());
    for (code, why) in UNTRIGGERABLE {
        assert!(
            !emitted.contains(code),
            "{code} is triggered now: remove it from UNTRIGGERABLE ({why})"
        );
        emitted.insert(*code);
    }
    let missing: Vec<&str> = Code::ALL
        .iter()
        .filter(|c| !emitted.contains(*c))
        .map(|c| c.as_str())
        .collect();
    assert!(
        missing.is_empty(),
        "registered but never emitted: {missing:#?}"
    );
}

fn bad_scene_codes() -> Vec<Code> {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/bad_scenes");
    let mut codes = Vec::new();
    for entry in std::fs::read_dir(dir).expect("bad_scenes folder") {
        let path = entry.expect("entry").path();
        if path.extension().is_some_and(|e| e == "scn") {
            codes.extend(codes_of(&compile_file(&path, &FsLoader::new())));
        }
    }
    codes.extend(codes_of(&compile_file(
        Path::new("tests/no_such_scene.scn"),
        &FsLoader::new(),
    )));
    codes
}

fn example_codes() -> Vec<Code> {
    let loader = example_loader();
    Code::ALL
        .iter()
        .filter(|c| from_source(**c))
        .filter_map(|c| example(c.explanation(), "Mistake"))
        .flat_map(|scn| codes_of(&compile_source("scene.scn", scn, &loader)).collect::<Vec<_>>())
        .collect()
}

fn include_chain_codes() -> Vec<Code> {
    let files: Vec<(String, Vec<u8>)> = (0..40)
        .map(|i| {
            (
                format!("a{i}.scn"),
                format!("scnc 1\ninclude \"a{}.scn\"\n", i + 1).into_bytes(),
            )
        })
        .collect();
    let mut loader = MemLoader::new();
    for (path, bytes) in files {
        loader.insert(path, bytes);
    }
    codes_of(&compile_source(
        "scene.scn",
        "scnc 1\ninclude \"a0.scn\"\n",
        &loader,
    ))
    .collect()
}

fn png(width: u32, height: u32) -> Vec<u8> {
    let mut out = Cursor::new(Vec::new());
    image::RgbImage::new(width, height)
        .write_to(&mut out, image::ImageFormat::Png)
        .expect("encode a tiny PNG");
    out.into_inner()
}

/// A PNG signature and header claiming `side` × `side` pixels, with no pixel data.
fn huge_png_header(side: u32) -> Vec<u8> {
    let mut chunk = b"IHDR".to_vec();
    chunk.extend(side.to_be_bytes());
    chunk.extend(side.to_be_bytes());
    chunk.extend([8, 2, 0, 0, 0]);
    let mut out = b"\x89PNG\r\n\x1a\n".to_vec();
    for chunk in [chunk, b"IDAT".to_vec(), b"IEND".to_vec()] {
        out.extend((chunk.len() as u32 - 4).to_be_bytes());
        out.extend(&chunk);
        out.extend(crc32(&chunk).to_be_bytes());
    }
    out
}

fn crc32(bytes: &[u8]) -> u32 {
    let mut crc = !0u32;
    for &b in bytes {
        crc ^= u32::from(b);
        for _ in 0..8 {
            crc = if crc & 1 == 1 {
                (crc >> 1) ^ 0xEDB8_8320
            } else {
                crc >> 1
            };
        }
    }
    !crc
}

/// A 2 × 1 PFM with the given RGB pixels.
fn pfm(pixels: [[f32; 3]; 2]) -> Vec<u8> {
    let mut out = b"PF\n2 1\n-1.0\n".to_vec();
    for p in pixels {
        for c in p {
            out.extend(c.to_le_bytes());
        }
    }
    out
}

fn build_stage_codes() -> Vec<Code> {
    let opts = BuildOptions::default();
    let files = mem(&[
        ("sky.pfm", pfm([[1.0; 3]; 2])),
        ("black.pfm", pfm([[0.0; 3]; 2])),
        ("nan.pfm", pfm([[f32::NAN, 1.0, 1.0], [1.0; 3]])),
        ("bad.png", b"not an image".to_vec()),
        ("huge.png", huge_png_header(100_000)),
        ("empty.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\n".to_vec()),
    ]);
    let scenes = [
        "mesh m = obj(\"nope.obj\")\nobject m { material grey }",
        "mesh m = obj(\"empty.obj\")\nobject m { material grey }",
        "mesh f = inline { positions [(0,0,0) (1,0,0) (2,0,0)]  indices [0 1 2] }\nobject f { material grey }",
        "mesh f = inline { positions [(0,0,0) (1,0,0) (0,1,0) (2,0,0)]  indices [0 1 2  0 1 3] }\nobject f { material grey }",
        "group g { transform { scale 1e-30 }\n object ball { material grey  transform { scale 1e-30 } } }",
        "light a = environment { image(\"sky.pfm\") }\nlight b = environment { image(\"sky.pfm\") }",
        "light a = environment { image(\"black.pfm\") }",
        "light a = environment { image(\"nan.pfm\") }",
        "texture t = image(\"bad.png\")\nmaterial m = phong { diffuse t }\nobject ball { material m }",
        "texture t = image(\"huge.png\")\nmaterial m = phong { diffuse t }\nobject ball { material m }",
        "light p = area { quad (0,2,0) (0,2,1) (1,2,1) (1,2,0)  radiance 5 }",
        "texture t = checker { even 0.2  odd 0.8 }\nmaterial m = phong { diffuse t }\nmesh f = inline { positions [(0,0,0) (1,0,0) (0,1,0)]  indices [0 1 2] }\nobject f { material m }",
    ];
    let mut codes: Vec<Code> = scenes
        .iter()
        .flat_map(|s| build_codes(&format!("{BASE}{s}\n"), &files, &opts))
        .collect();
    let no_camera = BuildOptions {
        camera: Some(99),
        ..BuildOptions::default()
    };
    codes.extend(build_codes(BASE, &files, &no_camera));
    // A directory where a file should be: exists, cannot be read (relative to the crate root).
    let dir_scene = format!("{BASE}mesh m = obj(\"tests\")\nobject m {{ material grey }}\n");
    codes.extend(build_codes(&dir_scene, &FsLoader::new(), &opts));
    for code in SELF_CONTAINED_BUILD {
        if let Some(mistake) = example(code.explanation(), "Mistake") {
            codes.extend(build_codes(mistake, &MemLoader::new(), &opts));
        }
    }
    codes
}

const WARN_MTL: &str = "Kd 0.5 0.5 0.5
newmtl wood
Kd 0.8 x 0.2
d 0.5
map_Kd nofile.png
newmtl bad
map_Kd bad.png
newmtl amb
map_Ns tiny.png
";

fn warn_obj() -> Vec<u8> {
    let mut obj =
        b"mtllib warn.mtl\nmtllib missing.mtl\nv 0 0 0\nv 1 0 0\nv 0 1 0\nl 1 2\ncstype bspline\n"
            .to_vec();
    for m in ["nosuch", "wood", "bad", "amb"] {
        obj.extend(format!("usemtl {m}\nf 1 2 3\n").as_bytes());
    }
    obj.extend(b"usemtl b\xe6r\nf 1 2 3\n");
    // A polygon above the ear-clipping limit: fanned.
    let n = scnc::assets::obj::polygon::EAR_CLIP_MAX + 4;
    for i in 0..n {
        let a = i as f32 / n as f32 * std::f32::consts::TAU;
        obj.extend(format!("v {} {} 0\n", a.cos(), a.sin()).as_bytes());
    }
    obj.extend(b"f");
    for i in 0..n {
        obj.extend(format!(" {}", i + 4).as_bytes());
    }
    obj.push(b'\n');
    obj
}

fn utf16_obj() -> Vec<u8> {
    let text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
    let mut out = vec![0xFF, 0xFE];
    for u in text.encode_utf16() {
        out.extend(u.to_le_bytes());
    }
    out
}

fn obj_codes() -> Vec<Code> {
    let tri = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";
    let files = mem(&[
        ("warn.obj", warn_obj()),
        ("warn.mtl", WARN_MTL.as_bytes().to_vec()),
        ("bad.png", b"not an image".to_vec()),
        ("tiny.png", png(2, 2)),
        ("utf16.obj", utf16_obj()),
        ("bad_number.obj", b"v 0 0,5 0\n".to_vec()),
        ("missing_number.obj", b"v 0 1\n".to_vec()),
        ("short_face.obj", format!("{tri}f 1 2\n").into_bytes()),
        ("bad_index.obj", format!("{tri}f 1 2 x\n").into_bytes()),
        ("index.obj", format!("{tri}f 1 2 4\n").into_bytes()),
        (
            "rewound.obj",
            format!("{tri}v 1 1 0\nf 1 2 4 3 1 2 4 3\n").into_bytes(),
        ),
        (
            "bowtie.obj",
            format!("{tri}v 1 1 0\nf 1 4 2 3\n").into_bytes(),
        ),
    ]);
    let mut scenes = vec![
        "mesh m = obj(\"warn.obj\") { material \"nothere\" grey }\nobject m { material grey }"
            .to_string(),
    ];
    for f in [
        "rewound",
        "bowtie",
        "utf16",
        "bad_number",
        "missing_number",
        "short_face",
        "bad_index",
        "index",
    ] {
        scenes.push(format!(
            "mesh m = obj(\"{f}.obj\")\nobject m {{ material grey }}"
        ));
    }
    scenes
        .iter()
        .flat_map(|s| build_codes(&format!("{BASE}{s}\n"), &files, &BuildOptions::default()))
        .collect()
}

fn write_codes() -> Vec<Code> {
    let film = Film::new(1, 1);
    let settings = scnc::film::WriteSettings::default();
    let dir = std::env::temp_dir().join("scnc_diag_registry_no_such_dir");
    [dir.join("out.unknown"), dir.join("out.png")]
        .iter()
        .filter_map(|p| {
            scnc::film::write_image(&film, p, &settings, scnc::film::Durability::Synced).err()
        })
        .map(|e| e.code())
        .collect()
}

/// Codes only the command line emits: run the binary, read the codes it prints.
fn cli_codes() -> Vec<Code> {
    let scnc = env!("CARGO_BIN_EXE_scnc");
    let root = env!("CARGO_MANIFEST_DIR");
    let out_png = std::env::temp_dir().join("scnc_diag_registry.png");
    let runs: [Vec<&str>; 2] = [
        vec!["render", "examples/cornell.scn", "--camera", "nope", "-o"],
        vec!["inspect", "tests/no_such_mesh.obj"],
    ];
    let mut codes = Vec::new();
    for args in runs {
        let mut cmd = Command::new(scnc);
        cmd.current_dir(root).args(&args);
        if args[0] == "render" {
            cmd.arg(&out_png);
        }
        let out = cmd.output().expect("run scnc");
        let stderr = String::from_utf8_lossy(&out.stderr);
        codes.extend(
            Code::ALL
                .iter()
                .filter(|c| stderr.contains(&format!("[{}]", c.as_str()))),
        );
    }
    codes
}

/// The codes of `scnc render --tile` and `scnc merge`: tiles of a tiny cornell box, then
/// merges that must fail.
fn tile_codes() -> Vec<Code> {
    let scnc = env!("CARGO_BIN_EXE_scnc");
    let cornell = concat!(env!("CARGO_MANIFEST_DIR"), "/examples/cornell.scn");
    let dir = std::env::temp_dir().join(format!("scnc_diag_registry_tiles_{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    let run = |args: &[&str]| {
        let out = Command::new(scnc)
            .current_dir(&dir)
            .args(args)
            .output()
            .expect("run scnc");
        String::from_utf8_lossy(&out.stderr).into_owned()
    };
    let small = ["--resolution", "8x6", "--spp", "1"];
    for (tile, spp, out) in [
        ("0/2", "1", "a.exr"),
        ("1/2", "1", "b.exr"),
        ("1/2", "4", "c.exr"),
    ] {
        let mut args = vec!["render", cornell, "--resolution", "8x6", "--spp", spp];
        args.extend(["--tile", tile, "-o", out]);
        run(&args);
    }
    std::fs::write(dir.join("cut.exr"), b"\x76\x2f\x31\x01").expect("write");
    let mut whole = vec!["render", cornell, "-o", "whole.exr"];
    whole.extend(small);
    run(&whole);
    let mut stderr = String::new();
    for args in [
        vec![
            "render",
            cornell,
            "--resolution",
            "8x6",
            "--tile",
            "0/2",
            "-o",
            "a.png",
        ],
        vec![
            "render",
            cornell,
            "--resolution",
            "8x6",
            "--tile",
            "0/7",
            "-o",
            "a.exr",
        ],
        vec![
            "render",
            cornell,
            "--resolution",
            "8x6",
            "--frames",
            "0..1",
            "-o",
            "f.png",
        ],
        vec![
            "render",
            cornell,
            "--resolution",
            "8x6",
            "--define",
            "nope=1",
            "-o",
            "a.png",
        ],
        vec![
            "render",
            cornell,
            "--resolution",
            "8x6",
            "--define",
            "red=2",
            "-o",
            "a.png",
        ],
        vec!["merge", "a.exr", "c.exr", "-o", "m.png"],
        vec!["merge", "a.exr", "a.exr", "b.exr", "-o", "m.png"],
        vec!["merge", "a.exr", "-o", "m.png"],
        vec!["merge", "a.exr", "cut.exr", "-o", "m.png"],
        vec!["merge", "a.exr", "whole.exr", "-o", "m.png"],
    ] {
        stderr.push_str(&run(&args));
    }
    let _ = std::fs::remove_dir_all(&dir);
    Code::ALL
        .iter()
        .copied()
        .filter(|c| stderr.contains(&format!("[{}]", c.as_str())))
        .collect()
}
