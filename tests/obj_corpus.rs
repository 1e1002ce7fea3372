//! A corpus of OBJ/MTL files as modelling tools write them, each written here in memory, with the
//! triangle count, area, materials and warnings (or the error and its line) scnc must make of it.

use scnc::assets::obj::polygon::newell;
use scnc::assets::obj::{load_obj, LoadedObj, ObjError};
use scnc::assets::MemLoader;

use std::path::Path;
use std::sync::Arc;

fn load_with(obj: &[u8], extra: &[(&str, &[u8])]) -> Result<LoadedObj, ObjError> {
    let mut loader = MemLoader::new();
    for (name, bytes) in extra {
        loader.insert(Path::new("dir").join(name), bytes.to_vec());
    }
    load_obj(Path::new("dir/m.obj"), Arc::from(obj), true, &loader)
}

fn load(obj: &[u8]) -> LoadedObj {
    load_with(obj, &[]).expect("loads")
}

fn area(o: &LoadedObj) -> f32 {
    let p = &o.model.positions;
    o.model
        .triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| p[i as usize]);
            0.5 * (b - a).cross(c - a).length()
        })
        .sum()
}

fn codes(o: &LoadedObj) -> Vec<&'static str> {
    o.warnings.iter().map(|(_, n)| n.code.as_str()).collect()
}

fn materials(o: &LoadedObj) -> Vec<Option<String>> {
    o.model.runs.iter().map(|r| r.name.clone()).collect()
}

const TRI: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\n";

#[test]
fn latin1_material_names_are_read_with_a_warning() {
    let obj = [
        b"mtllib m.mtl\n".as_slice(),
        TRI.as_bytes(),
        b"usemtl b\xe6r\nf 1 2 3\n",
    ]
    .concat();
    let o = load_with(&obj, &[("m.mtl", b"newmtl b\xe6r\nKd 1 0 0\n")]).expect("loads");
    assert_eq!(materials(&o), vec![Some("bær".to_string())]);
    assert!(o.find_material("bær").is_some());
    assert_eq!(
        codes(&o),
        vec!["scnc::obj::not_utf8", "scnc::obj::not_utf8"]
    );
    assert_eq!(o.warnings[0].1.at.line, 5);
}

#[test]
fn utf16_files_are_transcoded() {
    let text = format!("{TRI}usemtl é\nf 1 2 3\n");
    let mut bytes = vec![0xFF, 0xFE];
    for u in text.encode_utf16() {
        bytes.extend(u.to_le_bytes());
    }
    let o = load(&bytes);
    assert_eq!(o.model.triangles.len(), 1);
    assert_eq!(
        codes(&o),
        vec!["scnc::obj::utf16", "scnc::obj::unknown_material"]
    );
    assert_eq!(materials(&o), vec![Some("é".to_string())]);
}

#[test]
fn crlf_tabs_number_forms_and_no_final_newline() {
    let o = load(b"v +1 0 0\r\nv\t2. 0\t 0\r\nv 1e+2 1E2 0 \r\n\r\nf 1 2 3");
    assert_eq!(o.model.triangles.len(), 1);
    assert_eq!(o.model.positions[2], glam::Vec3::new(100.0, 100.0, 0.0));
    assert!(codes(&o).is_empty());
    assert!((area(&o) - 50.0).abs() < 1e-4);
}

#[test]
fn concave_polygon_is_ear_clipped_to_its_newell_area() {
    // An L-shaped hexagon plus a comb: fans from corner 0 would cover area outside both.
    let pts = [
        (0.0, 0.0),
        (4.0, 0.0),
        (4.0, 1.0),
        (1.0, 1.0),
        (1.0, 3.0),
        (3.0, 3.0),
        (3.0, 4.0),
        (0.0, 4.0),
    ];
    let mut obj = String::new();
    for (x, y) in pts {
        obj += &format!("v {x} 0 {y}\n");
    }
    obj += "f 8 7 6 5 4 3 2 1\n";
    let o = load(obj.as_bytes());
    assert_eq!(o.model.triangles.len(), 6);
    let corners: Vec<glam::Vec3> = o.model.positions.clone();
    let want = 0.5 * newell(&corners).length();
    assert!((area(&o) - want).abs() < 1e-5, "{} vs {want}", area(&o));
    assert!((want - 9.0).abs() < 1e-6);
}

#[test]
fn lines_and_points_are_skipped_in_one_warning() {
    let o = load(format!("{TRI}l 1 2\nl 2 3 1\np 1\nf 1 2 3\n").as_bytes());
    assert_eq!(o.model.triangles.len(), 1);
    assert_eq!(codes(&o), vec!["scnc::obj::lines_skipped"]);
    let n = &o.warnings[0].1;
    assert!(n.message.starts_with("3 line"), "{}", n.message);
    assert_eq!(n.at.line, 4);
}

#[test]
fn negative_indices_count_back() {
    let o = load(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf -3 -2 -1\nv 1 1 0\nf -3 -1 -2\n");
    assert_eq!(o.model.triangles, vec![[0, 1, 2], [1, 3, 2]]);
}

#[test]
fn missing_mtl_is_a_warning_at_the_obj_line() {
    let o = load(format!("{TRI}mtllib gone.mtl\nusemtl red\nf 1 2 3\n").as_bytes());
    assert_eq!(
        codes(&o),
        vec!["scnc::obj::missing_mtl", "scnc::obj::unknown_material"]
    );
    assert_eq!(o.warnings[0].1.at.line, 4);
    assert_eq!(o.model.triangles.len(), 1);
}

#[test]
fn mtllib_anywhere_with_spaces_in_names_and_usemtl_switches() {
    let obj = format!(
        "o house\n{TRI}v 1 1 0\ng walls\nusemtl my red\nf 1 2 3\nusemtl blue\nf 2 4 3\ns 1\n\
         usemtl my red\nf 1 2 4\nmtllib my lib.mtl\n"
    );
    let mtl = b"newmtl my red\nKd 1 0 0\nnewmtl blue\nKd 0 0 1\nKe 2 2 2\n";
    let o = load_with(obj.as_bytes(), &[("my lib.mtl", mtl)]).expect("loads");
    assert_eq!(
        materials(&o),
        vec![
            Some("my red".into()),
            Some("blue".into()),
            Some("my red".into())
        ]
    );
    assert_eq!(
        o.model.runs.iter().map(|r| r.start).collect::<Vec<_>>(),
        vec![0, 1, 2]
    );
    assert!(codes(&o).is_empty(), "{:?}", o.warnings);
    let (lib, m) = o.find_material("blue").expect("defined");
    assert_eq!(
        o.mtls[lib].library.materials[m].ke,
        Some(glam::Vec3::splat(2.0))
    );
    assert_eq!(o.model.stats.groups, 2);
}

#[test]
fn two_libraries_on_one_line() {
    let obj = format!("mtllib a.mtl b.mtl\n{TRI}usemtl y\nf 1 2 3\n");
    let o = load_with(
        obj.as_bytes(),
        &[("a.mtl", b"newmtl x\n"), ("b.mtl", b"newmtl y\nKd 1 1 0\n")],
    )
    .expect("loads");
    assert_eq!(o.mtls.len(), 2);
    assert_eq!(o.find_material("y"), Some((1, 0)));
    assert!(codes(&o).is_empty());
}

#[test]
fn vertex_colours_are_ignored() {
    let o = load(b"v 0 0 0 1 0 0\nv 1 0 0 0 1 0\nv 0 1 0 0 0 1\nf 1 2 3\n");
    assert_eq!(o.model.positions[1], glam::Vec3::X);
    assert!(codes(&o).is_empty());
}

#[test]
fn quads_split_on_the_shorter_diagonal_and_degenerates_are_counted() {
    let o = load(b"v 0 0 0\nv 3 0 0\nv 4 1 0\nv 1 1 0\nf 1 2 3 4\nf 1 2 2\nf 1 1 1 2\n");
    assert_eq!(o.model.triangles, vec![[1, 2, 3], [1, 3, 0]]);
    assert_eq!(o.model.stats.degenerate_dropped, 3);
}

#[test]
fn unsupported_statements_are_listed_once() {
    let o = load(format!("{TRI}vp 0.5\ncstype bezier\nvp 1\nf 1 2 3\n").as_bytes());
    assert_eq!(codes(&o), vec!["scnc::obj::unsupported_statement"]);
    let m = &o.warnings[0].1.message;
    assert!(
        m.contains("`vp` (2×, first on line 4)") && m.contains("`cstype` (line 5)"),
        "{m}"
    );
}

#[test]
fn corners_with_different_normals_get_their_own_vertices() {
    // A corner of a cube: one position, three faces with three normals and UVs.
    let o = load(
        b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nvn 0 0 -1\nvn 0 -1 0\nvn -1 0 0\nvt 0 0\n\
          f 1/1/1 3/1/1 2/1/1\nf 1/1/2 2/1/2 4/1/2\nf 1/1/3 4/1/3 3/1/3\n",
    );
    assert_eq!(o.model.triangles.len(), 3);
    // Positions 1-4 keep their first pairing; five corners pair differently.
    assert_eq!(o.model.positions.len(), 4 + 5);
    assert_eq!(o.model.normals.len(), o.model.positions.len());
    assert_eq!(o.model.uvs.len(), o.model.positions.len());
    for t in &o.model.triangles {
        let n = o.model.normals[t[0] as usize];
        assert!(t.iter().all(|&i| o.model.normals[i as usize] == n));
    }
    assert_eq!((o.model.stats.normals, o.model.stats.uvs), (3, 1));
}

#[test]
fn corners_without_normals_get_face_normals() {
    let o = load(b"v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\nf 2 4 3\n");
    assert_eq!(o.model.normals.len(), o.model.positions.len());
    assert!(o
        .model
        .normals
        .iter()
        .all(|n| (n.normalize() - glam::Vec3::Z).length() < 1e-6));
}

#[test]
fn errors_name_their_line() {
    let cases: &[(&str, &str, u32)] = &[
        (
            "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n",
            "scnc::obj::index_out_of_range",
            4,
        ),
        ("v 0 0 0\nf 0 1 1\n", "scnc::obj::index_out_of_range", 2),
        ("v 0 0 0\nv 1 zero 0\n", "scnc::obj::bad_number", 2),
        ("v 0 0\n", "scnc::obj::missing_number", 1),
        ("v 0 0 0\nv 1 0 0\n\nf 1 2\n", "scnc::obj::short_face", 4),
        ("v 0 0 0\nf 1/x 1 1\n", "scnc::obj::bad_index", 2),
        ("v 0 0 0\nf 1//1 1 1\n", "scnc::obj::index_out_of_range", 2),
    ];
    for &(text, code, line) in cases {
        let e = load_with(text.as_bytes(), &[]).expect_err(text);
        assert_eq!((e.code.as_str(), e.at.line), (code, line), "{text}");
    }
}

#[test]
fn mtl_problems_are_warnings_in_the_mtl() {
    let obj = format!("mtllib m.mtl\n{TRI}usemtl a\nf 1 2 3\n");
    let mtl = b"newmtl a\nKd 1 1\nd 0.5\nTr 0.5\nillum 7\n";
    let o = load_with(obj.as_bytes(), &[("m.mtl", mtl)]).expect("loads");
    assert_eq!(
        codes(&o),
        vec!["scnc::obj::bad_mtl_statement", "scnc::obj::unsupported_mtl"]
    );
    assert_eq!(o.warnings[0].1.at.line, 2);
    assert!(matches!(
        o.warnings[0].0,
        scnc::assets::obj::load::FileRef::Mtl(0)
    ));
}

#[test]
fn empty_and_comment_only_files_load_with_no_triangles() {
    for text in ["", "# nothing\n", "\n\n\r\n", "   \t"] {
        let o = load(text.as_bytes());
        assert!(o.model.triangles.is_empty());
    }
}
