//! The Kubernetes manifests in `examples/cluster/kubernetes/` against the official `batch/v1`
//! Job schema, with `kubernetes-validate` (PyPI; it ships the schemas of each Kubernetes
//! release, so no cluster and no network are needed; `.ci/run` installs it into the virtual
//! environment `target/ci-venv`, looked for here as in `tests/cluster_slurm.rs`; a
//! `KUBERNETES_VALIDATE` path or the `PATH` serve elsewhere). Strict mode rejects unknown fields, and a deliberately broken copy
//! must be rejected, so the check is known to bite. Where the tool is not installed the test
//! prints a loud `SKIPPED` to stderr and passes.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The Kubernetes release validated against: the first with `backoffLimitPerIndex` GA.
const KUBERNETES: &str = "1.33.0";

fn validator() -> Option<PathBuf> {
    let named = std::env::var_os("KUBERNETES_VALIDATE").map(PathBuf::from);
    let ci_venv =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("target/ci-venv/bin/kubernetes-validate");
    let candidates = named.into_iter().chain([ci_venv]).chain(
        std::env::var_os("PATH")
            .map(|p| {
                std::env::split_paths(&p)
                    .map(|d| d.join("kubernetes-validate"))
                    .collect::<Vec<_>>()
            })
            .unwrap_or_default(),
    );
    candidates.into_iter().find(|p| p.is_file())
}

fn validate(tool: &Path, files: &[PathBuf]) -> Output {
    Command::new(tool)
        .args(["--strict", "--no-warn", "-k", KUBERNETES])
        .args(files)
        .output()
        .expect("kubernetes-validate runs")
}

#[test]
fn the_job_manifests_match_the_batch_v1_schema_and_a_broken_one_does_not() {
    let Some(tool) = validator() else {
        // Straight to stderr: the test harness captures `eprintln!` of passing tests.
        let _ = writeln!(
            std::io::stderr(),
            "\n*** cluster_kubernetes SKIPPED: kubernetes-validate is not installed \
             (pip install kubernetes-validate, or run .ci/run) ***\n"
        );
        return;
    };
    let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("examples/cluster/kubernetes");
    let mut manifests: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("examples/cluster/kubernetes exists")
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|e| e == "yaml"))
        .collect();
    manifests.sort();
    assert_eq!(manifests.len(), 3, "{manifests:?}");
    let out = validate(&tool, &manifests);
    assert!(
        out.status.success(),
        "the manifests do not validate:\n{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let tiles =
        std::fs::read_to_string(dir.join("render-tiles-job.yaml")).expect("render-tiles-job.yaml");
    assert!(tiles.contains("completionMode: Indexed") && tiles.contains("JOB_COMPLETION_INDEX"));
    let tmp = std::env::temp_dir().join(format!("scnc-k8s-{}", std::process::id()));
    std::fs::create_dir_all(&tmp).expect("temp dir");
    for (name, from, to) in [
        (
            "misspelt.yaml",
            "backoffLimitPerIndex:",
            "backoffLimitPerIdx:",
        ),
        ("mistyped.yaml", "completions: 16", "completions: sixteen"),
    ] {
        let broken = tiles.replace(from, to);
        assert_ne!(broken, tiles, "{from} is in render-tiles-job.yaml");
        let path = tmp.join(name);
        std::fs::write(&path, broken).expect("write the broken copy");
        let out = validate(&tool, &[path]);
        assert!(
            !out.status.success(),
            "a manifest with {to} was accepted:\n{}",
            String::from_utf8_lossy(&out.stdout)
        );
    }
    let _ = std::fs::remove_dir_all(&tmp);
}
