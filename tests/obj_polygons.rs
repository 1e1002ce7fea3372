//! OBJ faces that cannot be triangulated as written (issue 19): a face that goes round the same
//! corners several times is triangulated once, and a face whose triangles miss its Newell area
//! (self-intersecting, folded) is reported; each warning sits at the face's line.

use scnc::assets::obj::polygon::newell;
use scnc::assets::obj::{parse_obj, ObjModel};

fn parse(text: &str) -> ObjModel {
    parse_obj(text.as_bytes()).expect("the file loads").0
}

fn area(m: &ObjModel) -> f32 {
    m.triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| m.positions[i as usize]);
            0.5 * (b - a).cross(c - a).length()
        })
        .sum()
}

const SQUARE: &str = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 2 0\n";

#[test]
fn a_face_listing_its_corners_many_times_is_triangulated_once_with_a_warning() {
    let wound = format!(
        "{SQUARE}f 1 2 3\n{}\n",
        "f".to_owned() + &" 1 2 3 5 4".repeat(40)
    );
    let m = parse(&wound);
    let once = parse(&format!("{SQUARE}f 1 2 3\nf 1 2 3 5 4\n"));
    assert_eq!(m.triangles, once.triangles);
    let p = &m.positions;
    let pentagon = [p[0], p[1], p[2], p[4], p[3]];
    assert!((area(&m) - 0.5 - 0.5 * newell(&pentagon).length()).abs() < 1e-5);
    let codes: Vec<_> = m
        .warnings
        .iter()
        .map(|n| (n.code.as_str(), n.at.line))
        .collect();
    assert_eq!(codes, vec![("scnc::obj::polygon_rewound", 7)]);
    assert!(
        m.warnings[0].message.contains("same 5 corners"),
        "{}",
        m.warnings[0].message
    );
    assert!(once.warnings.is_empty());
}

#[test]
fn self_intersecting_faces_are_reported_once_with_their_count() {
    // Two bow ties (lines 6 and 7) and a good square between.
    let text = format!("{SQUARE}f 1 3 2 4\nf 1 2 3 4\nf 2 4 1 3\n");
    let m = parse(&text);
    let notes: Vec<_> = m
        .warnings
        .iter()
        .map(|n| (n.code.as_str(), n.at.line))
        .collect();
    assert_eq!(notes, vec![("scnc::obj::polygon_area", 6)]);
    assert!(
        m.warnings[0].message.starts_with("2 faces"),
        "{}",
        m.warnings[0].message
    );
}

#[test]
fn warped_and_concave_faces_are_not_reported() {
    // A quad with one corner lifted, a concave hexagon, far from the origin.
    let text = "v 1e5 1e5 1e5\nv 100001 1e5 1e5\nv 100001 100001 100000.3\nv 1e5 100001 1e5\n\
                v 0 0 0\nv 4 0 0\nv 4 3 0\nv 2 1 0\nv 0 3 0\nv -1 1 0\n\
                f 1 2 3 4\nf 5 6 7 8 9 10\n";
    assert!(parse(text).warnings.is_empty());
}
