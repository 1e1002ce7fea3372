//! Stage 5: output formats round-trip, and writes are atomic.

use std::fs;
use std::path::PathBuf;

use glam::Vec3;
use scnc::film::{
    format_for_path, write_atomic_with, write_image, Durability, Film, WriteError, WriteSettings,
};
use scnc::ir::{OutputFormat, ToneMap};

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("scnc-film-{}-{name}", std::process::id()));
    let _ = fs::remove_dir_all(&dir);
    fs::create_dir_all(&dir).expect("temp dir is writable");
    dir
}

fn gradient(w: u32, h: u32) -> Film {
    let mut f = Film::new(w, h);
    for y in 0..h {
        for x in 0..w {
            f.set(
                x,
                y,
                Vec3::new(x as f32 / w as f32, y as f32 / h as f32, 2.5),
            );
        }
    }
    f
}

fn leftovers(dir: &PathBuf) -> Vec<String> {
    fs::read_dir(dir)
        .expect("dir exists")
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".tmp"))
        .collect()
}

#[test]
fn formats_follow_the_extension() {
    let f = |p: &str| format_for_path(p.as_ref());
    assert_eq!(f("a.png"), Some(OutputFormat::Png));
    assert_eq!(f("dir/a.EXR"), Some(OutputFormat::Exr));
    assert_eq!(f("a.hdr"), Some(OutputFormat::Hdr));
    assert_eq!(f("a.pfm"), Some(OutputFormat::Pfm));
    assert_eq!(f("a.jpg"), None);
    assert_eq!(f("noext"), None);
}

#[test]
fn png_exr_hdr_round_trip() {
    let dir = scratch("roundtrip");
    let film = gradient(7, 5);
    let settings = WriteSettings {
        exposure: 0.0,
        tonemap: ToneMap::Clamp,
    };
    for ext in ["png", "exr", "hdr"] {
        let path = dir.join(format!("out.{ext}"));
        write(&film, &path, &settings).expect("writable");
        let img = image::open(&path).expect("readable").into_rgb32f();
        assert_eq!((img.width(), img.height()), (7, 5), "{ext}");
        let px = img.get_pixel(3, 4);
        let expected = film.get(3, 4);
        match ext {
            // Clamped, sRGB-encoded, 8-bit: the image crate decodes the bytes as 0..1 values.
            "png" => {
                let srgb = scnc::film::tonemap::srgb_encode(expected.x);
                assert!((px[0] - srgb).abs() < 1.0 / 255.0);
                assert_eq!(px[2], 1.0);
            }
            "exr" => assert_eq!(Vec3::from(px.0), expected),
            // RGBE keeps 8 bits of mantissa per channel relative to the largest.
            _ => assert!((Vec3::from(px.0) - expected).abs().max_element() < 0.02 * 2.5),
        }
    }
    assert!(leftovers(&dir).is_empty());
}

#[test]
fn pfm_is_little_endian_bottom_row_first() {
    let dir = scratch("pfm");
    let film = gradient(3, 2);
    let path = dir.join("out.pfm");
    write(&film, &path, &WriteSettings::default()).expect("writable");
    let bytes = fs::read(&path).expect("written");
    let header = b"PF\n3 2\n-1.0\n";
    assert_eq!(&bytes[..header.len()], header);
    let floats: Vec<f32> = bytes[header.len()..]
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    assert_eq!(floats.len(), 3 * 2 * 3);
    // The first stored pixel is the bottom-left one (row 1).
    assert_eq!(Vec3::new(floats[0], floats[1], floats[2]), film.get(0, 1));
    assert_eq!(Vec3::new(floats[9], floats[10], floats[11]), film.get(0, 0));
}

/// `scnc render`'s write: synced.
fn write(film: &Film, path: &std::path::Path, settings: &WriteSettings) -> Result<(), WriteError> {
    write_image(film, path, settings, Durability::Synced)
}

#[test]
fn a_failing_write_leaves_the_previous_file_and_no_temp() {
    for durability in [Durability::Synced, Durability::Replaced] {
        let dir = scratch(&format!("atomic-{durability:?}"));
        let target = dir.join("image.png");
        fs::write(&target, b"previous image").expect("writable");
        let err = write_atomic_with(&target, durability, |f| {
            use std::io::Write;
            f.write_all(b"half an ima")?;
            Err(std::io::Error::other("disk full"))
        })
        .expect_err("the fill failed");
        assert_eq!(err.to_string(), "disk full");
        assert_eq!(fs::read(&target).expect("still there"), b"previous image");
        assert!(leftovers(&dir).is_empty(), "{:?}", leftovers(&dir));

        // A real write replaces it, the same bytes either way.
        let film = gradient(2, 2);
        write_image(&film, &target, &WriteSettings::default(), durability).expect("writable");
        assert!(image::open(&target).is_ok());
        let synced = dir.join("synced.png");
        write(&film, &synced, &WriteSettings::default()).expect("writable");
        assert_eq!(fs::read(&target).unwrap(), fs::read(&synced).unwrap());
        assert!(leftovers(&dir).is_empty(), "{:?}", leftovers(&dir));
    }
}

#[test]
fn writing_over_a_directory_fails_cleanly() {
    let dir = scratch("isdir");
    let target = dir.join("taken.png");
    fs::create_dir(&target).expect("writable");
    fs::write(target.join("keep.txt"), b"keep").expect("writable");
    let err = write(&gradient(2, 2), &target, &WriteSettings::default()).expect_err("a directory");
    assert!(matches!(err, WriteError::Io { .. }));
    assert_eq!(err.to_diagnostic(None).code, "scnc::write::io");
    assert_eq!(
        fs::read(target.join("keep.txt")).expect("untouched"),
        b"keep"
    );
    assert!(leftovers(&dir).is_empty());

    let missing_dir = dir.join("no/such/dir/out.png");
    assert!(matches!(
        write(&gradient(2, 2), &missing_dir, &WriteSettings::default()),
        Err(WriteError::Io { .. })
    ));
    let unknown = write(
        &gradient(2, 2),
        &dir.join("x.jpg"),
        &WriteSettings::default(),
    );
    assert!(matches!(unknown, Err(WriteError::UnknownFormat { .. })));
}
