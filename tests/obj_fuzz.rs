//! Seeded mutation of OBJ and MTL bytes (truncation, byte flips, inserted lines with huge
//! indices and counts, spliced fragments): no panic, no hang, and output bounded by the input
//! (triangles and vertices at most one per input byte: memory proportional to the file).
//! The normal suite runs 1,000 cases; `cargo test --release --test obj_fuzz -- --ignored` runs
//! 100,000.

use std::path::Path;
use std::sync::Arc;
use std::time::{Duration, Instant};

use scnc::assets::obj::load_obj;
use scnc::assets::MemLoader;

const OBJ: &str =
    "# cube-ish\r\nmtllib m.mtl\no a\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1 1 0 0\n\
vt 0 0\nvt 1 0 .5\nvn 0 0 1\nvn 0 1 0\ng g1\nusemtl red\nf 1/1/1 2/2/1 3/1/1 4/2/1\ns off\n\
f -1 -2 -3\nusemtl blue\nf 1//2 5//2 2//2\nf 1 2 3 4 5\nl 1 2 3\np 4\nvp 1 2\nf 5/1 4/2 3/1\n";
const MTL: &str = "newmtl red\nKd 1 0 0\nKs 0.5 0.5 0.5\nNs 20\nmap_Kd -s 1 1 1 r.png\n\
newmtl blue\nKd 0 0 1\nKe 1 1 1\nbump -bm 0.5 b.png\nd 0.5\nillum 5\n";

struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        self.0
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

const SPLICES: &[&[u8]] = &[
    b"\nf 99999999999 1 2\n",
    b"\nf 2147483647 -2147483648 1\n",
    b"\nf -99 1 2\n",
    b"\nv 1e39 -1e39 nan\n",
    b"\nv inf 0 0\n",
    b"\nusemtl \xff\xfe\n",
    b"\nmtllib  \n",
    b"\nf 1/1/1/1 2//// 3\n",
    b"\\\n",
    b"\r",
    b"\x00",
    b"\xff\xfe",
];

fn mutate(rng: &mut Rng, base: &[u8]) -> Vec<u8> {
    let mut b = base.to_vec();
    for _ in 0..1 + rng.below(4) {
        match rng.below(6) {
            0 => b.truncate(rng.below(b.len() + 1)),
            1 => {
                for _ in 0..1 + rng.below(8) {
                    if !b.is_empty() {
                        let i = rng.below(b.len());
                        b[i] ^= 1 << rng.below(8);
                    }
                }
            }
            2 => {
                let s = SPLICES[rng.below(SPLICES.len())];
                let at = rng.below(b.len() + 1);
                b.splice(at..at, s.iter().copied());
            }
            3 => {
                // A huge polygon: thousands of corners (ear clipping must stay bounded).
                let n = 100 + rng.below(6000);
                let mut line = b"\nf".to_vec();
                for k in 0..n {
                    line.extend(format!(" {}", 1 + (k * 7 + rng.below(3)) % 5).bytes());
                }
                line.push(b'\n');
                b.extend(line);
            }
            4 => {
                // Duplicate a random range (long lines, repeated statements).
                let s = rng.below(b.len() + 1);
                let e = (s + rng.below(200)).min(b.len());
                let chunk = b[s..e].to_vec();
                b.splice(s..s, chunk);
            }
            _ => {
                let i = rng.below(b.len() + 1);
                b.insert(i.min(b.len()), rng.next() as u8);
            }
        }
    }
    b
}

fn run(cases: usize, seed: u64) {
    let mut rng = Rng(seed);
    let start = Instant::now();
    let mut loaded = 0;
    for case in 0..cases {
        let obj = mutate(&mut rng, OBJ.as_bytes());
        let mtl = mutate(&mut rng, MTL.as_bytes());
        let mut loader = MemLoader::new();
        loader.insert("d/m.mtl", mtl);
        let t = Instant::now();
        let result = load_obj(Path::new("d/m.obj"), Arc::from(obj.clone()), true, &loader);
        assert!(
            t.elapsed() < Duration::from_secs(2),
            "case {case} took {:?}",
            t.elapsed()
        );
        if let Ok(o) = result {
            loaded += 1;
            let m = &o.model;
            assert!(
                m.triangles.len() <= obj.len(),
                "case {case}: triangles not bounded"
            );
            assert!(
                m.positions.len() <= obj.len(),
                "case {case}: vertices not bounded"
            );
            let n = m.positions.len();
            assert!(
                m.triangles.iter().flatten().all(|&i| (i as usize) < n),
                "case {case}"
            );
            assert!(m.normals.is_empty() || m.normals.len() == n);
            assert!(m.uvs.is_empty() || m.uvs.len() == n);
            assert!(m.runs.windows(2).all(|w| w[0].start <= w[1].start));
        }
    }
    // Most mutants still load: the parser is forgiving, not just non-crashing.
    assert!(loaded * 4 > cases, "only {loaded} of {cases} loaded");
    eprintln!("{cases} cases in {:?}, {loaded} loaded", start.elapsed());
}

#[test]
fn a_thousand_mutants_never_panic_or_hang() {
    run(1000, 0x5EED_0B1E);
}

#[test]
#[ignore = "100,000 cases: run with --release --ignored"]
fn a_hundred_thousand_mutants() {
    run(100_000, 0xC0FF_EE00_D15E_A5E5);
}
