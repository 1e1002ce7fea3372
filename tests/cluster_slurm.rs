//! Past one machine, for real (issue 18): the Slurm example of `examples/cluster/slurm/` run on
//! a single-node Slurm cluster that this test brings up on localhost from Debian's packages
//! (`slurm-wlm`, `munge`; `.ci/run` installs them). The tile array and the dependent merge job
//! are submitted with the example's own `submit.sh`, waited for with `squeue`, and the merged
//! image must be the bytes a single-process render writes.
//!
//! Where Slurm cannot start (not root, packages missing, a daemon that does not come up) the
//! test says so on stderr, loudly, and passes: it needs a machine, not just a compiler.
//!
//! The Kubernetes manifests are checked against the batch/v1 Job schema with
//! `kubernetes-validate` (PyPI; the Job schema of Kubernetes 1.37, strict: unknown fields and
//! wrong types fail), which `.ci/run` installs; a manifest broken on purpose must fail.

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const SCNC: &str = env!("CARGO_BIN_EXE_scnc");

fn skip(what: &str, reason: &str) {
    eprintln!("\n*** SKIPPED {what}: {reason} ***\n");
}

fn on_path(bin: &str) -> bool {
    Command::new("sh")
        .args(["-c", &format!("command -v {bin}")])
        .stdout(Stdio::null())
        .status()
        .is_ok_and(|s| s.success())
}

fn is_root() -> bool {
    Command::new("id")
        .arg("-u")
        .output()
        .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "0")
}

/// The daemons of the test cluster; killed when dropped, whatever happened.
struct Cluster {
    dir: PathBuf,
    daemons: Vec<Child>,
}

impl Drop for Cluster {
    fn drop(&mut self) {
        for d in &mut self.daemons {
            let _ = d.kill();
            let _ = d.wait();
        }
        if std::env::var_os("SCNC_KEEP_SLURM").is_none() {
            let _ = std::fs::remove_dir_all(&self.dir);
        }
    }
}

impl Cluster {
    fn conf(&self) -> PathBuf {
        self.dir.join("slurm.conf")
    }

    fn command(&self, bin: &str) -> Command {
        let mut c = Command::new(bin);
        c.env("SLURM_CONF", self.conf());
        c
    }

    fn log(&self, name: &str) -> String {
        std::fs::read_to_string(self.dir.join("log").join(name)).unwrap_or_default()
    }

    /// Starts munged, slurmctld and slurmd in `dir`; `Err` says why it could not.
    fn start(dir: PathBuf) -> Result<Cluster, String> {
        let _ = std::fs::remove_dir_all(&dir);
        for sub in ["state", "spool", "log"] {
            std::fs::create_dir_all(dir.join(sub)).map_err(|e| e.to_string())?;
        }
        let mut cluster = Cluster {
            dir: dir.clone(),
            daemons: Vec::new(),
        };
        let key = dir.join("munge.key");
        let mut random = vec![0u8; 1024];
        std::fs::File::open("/dev/urandom")
            .and_then(|mut f| std::io::Read::read_exact(&mut f, &mut random))
            .map_err(|e| format!("/dev/urandom: {e}"))?;
        std::fs::write(&key, &random).map_err(|e| e.to_string())?;
        Command::new("chmod")
            .args(["600", &key.display().to_string()])
            .status()
            .map_err(|e| e.to_string())?;
        let socket = dir.join("munge.sock");
        let munged = Command::new("munged")
            .arg("--foreground")
            .arg(format!("--key-file={}", key.display()))
            .arg(format!("--socket={}", socket.display()))
            .arg(format!("--pid-file={}", dir.join("munged.pid").display()))
            .arg(format!(
                "--log-file={}",
                dir.join("log/munged.log").display()
            ))
            .arg(format!("--seed-file={}", dir.join("munge.seed").display()))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .map_err(|e| format!("munged: {e}"))?;
        cluster.daemons.push(munged);
        wait_for(Duration::from_secs(10), || socket.exists())
            .map_err(|_| "munged did not open its socket".to_string())?;
        let host = Command::new("hostname")
            .arg("-s")
            .output()
            .map(|o| String::from_utf8_lossy(&o.stdout).trim().to_string())
            .map_err(|e| e.to_string())?;
        // Ports away from Slurm's defaults, per process, so a system Slurm is left alone.
        let port = 20_000 + (std::process::id() % 20_000) as u16;
        let d = dir.display();
        let conf = format!(
            "ClusterName=scnctest\nSlurmctldHost={host}(127.0.0.1)\nSlurmUser=root\n\
             SlurmdUser=root\nAuthType=auth/munge\nAuthInfo=socket={d}/munge.sock\n\
             CredType=cred/munge\nStateSaveLocation={d}/state\nSlurmdSpoolDir={d}/spool\n\
             SlurmctldPidFile={d}/slurmctld.pid\nSlurmdPidFile={d}/slurmd.pid\n\
             SlurmctldLogFile={d}/log/slurmctld.log\nSlurmdLogFile={d}/log/slurmd.log\n\
             SlurmctldPort={port}\nSlurmdPort={}\nProctrackType=proctrack/linuxproc\n\
             TaskPlugin=task/none\nSchedulerType=sched/backfill\nSelectType=select/cons_tres\n\
             SelectTypeParameters=CR_Core\nReturnToService=2\n\
             JobAcctGatherType=jobacct_gather/none\nAccountingStorageType=accounting_storage/none\n\
             MpiDefault=none\nMinJobAge=300\n\
             NodeName={host} NodeAddr=127.0.0.1 CPUs=2 RealMemory=1000 State=UNKNOWN\n\
             PartitionName=scnc Nodes={host} Default=YES MaxTime=INFINITE State=UP\n",
            port + 1
        );
        std::fs::write(cluster.conf(), conf).map_err(|e| e.to_string())?;
        for (bin, args) in [("slurmctld", vec!["-D", "-c"]), ("slurmd", vec!["-D"])] {
            let child = cluster
                .command(bin)
                .args(&args)
                .stdout(Stdio::null())
                .stderr(Stdio::null())
                .spawn()
                .map_err(|e| format!("{bin}: {e}"))?;
            cluster.daemons.push(child);
        }
        wait_for(Duration::from_secs(30), || {
            cluster
                .command("sinfo")
                .args(["-h", "-o", "%t"])
                .output()
                .is_ok_and(|o| String::from_utf8_lossy(&o.stdout).trim() == "idle")
        })
        .map_err(|_| {
            format!(
                "the node never became idle; slurmctld log:\n{}\nslurmd log:\n{}",
                cluster.log("slurmctld.log"),
                cluster.log("slurmd.log")
            )
        })?;
        Ok(cluster)
    }
}

fn wait_for(limit: Duration, mut ready: impl FnMut() -> bool) -> Result<(), ()> {
    let start = Instant::now();
    while start.elapsed() < limit {
        if ready() {
            return Ok(());
        }
        std::thread::sleep(Duration::from_millis(250));
    }
    Err(())
}

fn example(path: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join(path)
}

#[test]
fn slurm_tile_array_and_merge_give_the_single_process_image() {
    const WHAT: &str = "the single-node Slurm test (tests/cluster_slurm.rs)";
    if !is_root() {
        return skip(
            WHAT,
            "it starts slurmctld, slurmd and munged, which needs root",
        );
    }
    if let Some(bin) = ["munged", "slurmctld", "slurmd", "sbatch", "squeue", "sinfo"]
        .into_iter()
        .find(|b| !on_path(b))
    {
        return skip(
            WHAT,
            &format!("{bin} is not installed (apt-get install slurm-wlm munge)"),
        );
    }
    let dir = std::env::temp_dir().join(format!("scnc-slurm-{}", std::process::id()));
    let cluster = match Cluster::start(dir.clone()) {
        Ok(c) => c,
        Err(why) => return skip(WHAT, &format!("Slurm did not start: {why}")),
    };
    let scene = example("examples/cornell.scn");
    let args = "--resolution 64x48 --spp 4";
    let parts = dir.join("parts");
    let merged = dir.join("merged.png");
    let submit = cluster
        .command("bash")
        .arg(example("examples/cluster/slurm/submit.sh"))
        .env("SCNC", SCNC)
        .env("SCENE", &scene)
        .env("N", "4")
        .env("OUT_DIR", &parts)
        .env("OUTPUT", &merged)
        .env("SCNC_ARGS", args)
        .output()
        .expect("bash runs");
    assert!(
        submit.status.success(),
        "submit.sh failed: {}",
        String::from_utf8_lossy(&submit.stderr)
    );
    let ids = String::from_utf8_lossy(&submit.stdout).trim().to_string();
    let jobs: Vec<&str> = ids.split_whitespace().collect();
    assert_eq!(
        jobs.len(),
        2,
        "submit.sh prints the array and merge job ids: {ids}"
    );
    // Wait until neither job is in the queue any more (the merge starts once every tile
    // succeeded; Slurm checks dependencies every few seconds).
    let finished = wait_for(Duration::from_secs(180), || {
        cluster
            .command("squeue")
            .args(["-h", "-j", &jobs.join(",")])
            .output()
            .is_ok_and(|o| o.status.success() && o.stdout.iter().all(u8::is_ascii_whitespace))
    });
    let logs = || {
        let mut s = String::new();
        for entry in std::fs::read_dir(&parts).into_iter().flatten().flatten() {
            if entry.path().extension().is_some_and(|e| e == "log") {
                s += &format!(
                    "--- {}\n{}",
                    entry.path().display(),
                    std::fs::read_to_string(entry.path()).unwrap_or_default()
                );
            }
        }
        s + &cluster.log("slurmctld.log")
    };
    assert!(
        finished.is_ok(),
        "the jobs did not finish in 180 s:\n{}",
        logs()
    );
    let tiles = (0..4)
        .filter(|k| parts.join(format!("part_{k}.exr")).is_file())
        .count();
    assert_eq!(tiles, 4, "every array task wrote its tile:\n{}", logs());
    assert!(
        merged.is_file(),
        "the merge job wrote the image:\n{}",
        logs()
    );
    let direct = dir.join("direct.png");
    let out = Command::new(SCNC)
        .arg("render")
        .arg(&scene)
        .args(args.split_whitespace())
        .arg("-o")
        .arg(&direct)
        .output()
        .expect("scnc runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(
        std::fs::read(&merged).ok() == std::fs::read(&direct).ok(),
        "the merged image differs from a single-process render"
    );
    drop(cluster);
}

/// `kubernetes-validate`, from the PATH or the virtual environment `.ci/run` makes.
fn kubernetes_validate() -> Option<PathBuf> {
    let venv = Path::new(env!("CARGO_MANIFEST_DIR")).join("target/ci-venv/bin/kubernetes-validate");
    if venv.is_file() {
        return Some(venv);
    }
    on_path("kubernetes-validate").then(|| PathBuf::from("kubernetes-validate"))
}

#[test]
fn kubernetes_manifests_are_valid_jobs() {
    let Some(validate) = kubernetes_validate() else {
        return skip(
            "the Kubernetes manifest check (tests/cluster_slurm.rs)",
            "kubernetes-validate is not installed (pip install kubernetes-validate)",
        );
    };
    let dir = example("examples/cluster/kubernetes");
    let mut manifests: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("the manifests folder")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "yaml"))
        .collect();
    manifests.sort();
    assert!(manifests.len() >= 2, "{manifests:?}");
    let run = |files: &[PathBuf]| {
        Command::new(&validate)
            .args(["--strict", "-k", "1.37.0"])
            .args(files)
            .output()
            .expect("kubernetes-validate runs")
    };
    let ok = run(&manifests);
    assert!(
        ok.status.success(),
        "{}{}",
        String::from_utf8_lossy(&ok.stdout),
        String::from_utf8_lossy(&ok.stderr)
    );
    // The check can fail: a misspelled field and a wrong type are rejected.
    let text = std::fs::read_to_string(dir.join("render-tiles-job.yaml")).expect("readable");
    for (from, to) in [
        ("backoffLimitPerIndex:", "backoffLimitPerIdx:"),
        ("completions: 16", "completions: sixteen"),
    ] {
        assert!(text.contains(from), "{from}");
        let bad = std::env::temp_dir().join(format!("scnc-bad-job-{}.yaml", std::process::id()));
        std::fs::write(&bad, text.replace(from, to)).expect("writable");
        let out = run(std::slice::from_ref(&bad));
        let _ = std::fs::remove_file(&bad);
        assert!(!out.status.success(), "{to} passed the schema check");
    }
}
