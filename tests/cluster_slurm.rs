//! The Slurm example (`examples/cluster/slurm/`) on a real, single-node Slurm cluster: the test
//! starts munged, slurmctld and slurmd from Debian's `slurm-wlm`/`munge` packages with a
//! minimal `slurm.conf` in a temporary directory (state and spool there too), submits the tile
//! array and the dependent merge job with the example's `submit.sh`, waits with `squeue`, and
//! checks that the merged PNG is byte-identical to a single-process render. The daemons are
//! killed when the test ends (also on failure). Where Slurm cannot start (not installed, not
//! root, a daemon fails) the test prints a loud `SKIPPED` to stderr and passes.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const SCNC: &str = env!("CARGO_BIN_EXE_scnc");
const TILES: u32 = 4;
const RENDER_ARGS: &str = "--resolution 64x48 --spp 4";

/// Straight to stderr: the test harness captures `eprintln!` of passing tests.
fn skip(reason: &str) {
    let _ = writeln!(
        std::io::stderr(),
        "\n*** cluster_slurm SKIPPED: {reason} ***\n"
    );
}

/// The daemons, killed and reaped on drop.
struct Daemons(Vec<Child>);

impl Drop for Daemons {
    fn drop(&mut self) {
        for child in self.0.iter_mut().rev() {
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

fn find(program: &str) -> Option<PathBuf> {
    [
        "/usr/sbin",
        "/usr/bin",
        "/sbin",
        "/bin",
        "/usr/local/bin",
        "/usr/local/sbin",
    ]
    .iter()
    .map(|d| Path::new(d).join(program))
    .find(|p| p.is_file())
}

fn output(cmd: &mut Command) -> Option<String> {
    let out = cmd.stderr(Stdio::null()).output().ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

fn slurm_conf(dir: &Path, host: &str, port: u32) -> String {
    let d = dir.display();
    format!(
        "ClusterName=scnctest\nSlurmctldHost={host}(127.0.0.1)\nSlurmctldPort={port}\n\
         SlurmdPort={}\nSlurmUser=root\nSlurmdUser=root\nAuthType=auth/munge\n\
         CredType=cred/munge\nAuthInfo=socket={d}/munge.socket\nStateSaveLocation={d}/state\n\
         SlurmdSpoolDir={d}/spool\nSlurmctldPidFile={d}/slurmctld.pid\n\
         SlurmdPidFile={d}/slurmd.pid\nSlurmctldLogFile={d}/slurmctld.log\n\
         SlurmdLogFile={d}/slurmd.log\nProctrackType=proctrack/linuxproc\nTaskPlugin=task/none\n\
         JobAcctGatherType=jobacct_gather/none\nAccountingStorageType=accounting_storage/none\n\
         SchedulerType=sched/backfill\nSelectType=select/cons_tres\nSelectTypeParameters=CR_Core\n\
         ReturnToService=2\nMpiDefault=none\nSwitchType=switch/none\nMinJobAge=300\n\
         NodeName={host} NodeAddr=127.0.0.1 CPUs=2 State=UNKNOWN\n\
         PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP\n",
        port + 1
    )
}

/// Starts munged, slurmctld and slurmd in `dir`; `Err` says why Slurm cannot run here.
fn start_cluster(dir: &Path) -> Result<(Daemons, PathBuf), String> {
    let mut tools = Vec::new();
    for p in [
        "munged",
        "slurmctld",
        "slurmd",
        "sbatch",
        "squeue",
        "scontrol",
        "sinfo",
    ] {
        tools.push(find(p).ok_or(format!(
            "`{p}` is not installed (apt-get install slurm-wlm munge)"
        ))?);
    }
    if output(Command::new("id").arg("-u")).as_deref() != Some("0") {
        return Err("not root: slurmd must run as root to launch jobs".into());
    }
    let host = output(Command::new("hostname").arg("-s")).ok_or("no hostname")?;
    for sub in ["state", "spool"] {
        std::fs::create_dir_all(dir.join(sub)).map_err(|e| e.to_string())?;
    }
    let key = dir.join("munge.key");
    let bytes: Vec<u8> = (0..1024u32)
        .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
        .collect();
    std::fs::write(&key, bytes).map_err(|e| e.to_string())?;
    let _ = Command::new("chmod").arg("600").arg(&key).status();
    // A port pair from the process id, so parallel runs on one machine do not collide.
    let port = 20_000 + (std::process::id() % 10_000) * 2;
    let conf = dir.join("slurm.conf");
    std::fs::write(&conf, slurm_conf(dir, &host, port)).map_err(|e| e.to_string())?;
    let mut daemons = Daemons(Vec::new());
    let spawn = |cmd: &mut Command| {
        cmd.env("SLURM_CONF", &conf)
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .map_err(|e| format!("{cmd:?}: {e}"))
    };
    daemons.0.push(spawn(
        Command::new(&tools[0])
            .arg("--foreground")
            .arg("--force")
            .arg(format!("--key-file={}", key.display()))
            .arg(format!("--socket={}/munge.socket", dir.display()))
            .arg(format!("--pid-file={}/munged.pid", dir.display()))
            .arg(format!("--log-file={}/munged.log", dir.display()))
            .arg(format!("--seed-file={}/munge.seed", dir.display())),
    )?);
    std::thread::sleep(Duration::from_millis(300));
    daemons
        .0
        .push(spawn(Command::new(&tools[1]).args(["-D", "-i"]))?);
    daemons.0.push(spawn(Command::new(&tools[2]).arg("-D"))?);
    let start = Instant::now();
    loop {
        let state = output(
            Command::new(&tools[6])
                .env("SLURM_CONF", &conf)
                .args(["-h", "-o", "%t"]),
        );
        if state.as_deref() == Some("idle") {
            return Ok((daemons, conf));
        }
        if start.elapsed() > Duration::from_secs(15) {
            return Err(format!(
                "the node did not come up in 15 s (sinfo: {state:?}; logs in {})",
                dir.display()
            ));
        }
        std::thread::sleep(Duration::from_millis(250));
    }
}

#[test]
fn a_tile_array_and_its_merge_on_slurm_equal_one_render() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let dir = std::env::temp_dir().join(format!("scnc-slurm-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("temp dir");
    let (daemons, conf) = match start_cluster(&dir) {
        Ok(c) => c,
        Err(reason) => return skip(&reason),
    };
    let out = dir.join("out");
    let scene = root.join("examples/cornell.scn");
    let submitted = Command::new(root.join("examples/cluster/slurm/submit.sh"))
        .env("SLURM_CONF", &conf)
        .env("SCNC", SCNC)
        .env("SCENE", &scene)
        .env("N", TILES.to_string())
        .env("OUT", &out)
        .env("SCNC_ARGS", RENDER_ARGS)
        .output()
        .expect("submit.sh runs");
    assert!(
        submitted.status.success(),
        "submit.sh failed: {}",
        String::from_utf8_lossy(&submitted.stderr)
    );
    let merge_job = String::from_utf8_lossy(&submitted.stdout)
        .trim()
        .to_string();
    assert!(
        merge_job.parse::<u64>().is_ok(),
        "merge job id: {merge_job:?}"
    );
    let start = Instant::now();
    loop {
        let queued = output(
            Command::new("squeue")
                .env("SLURM_CONF", &conf)
                .args(["-h", "-o", "%i %T"]),
        )
        .unwrap_or_default();
        if queued.is_empty() {
            break;
        }
        assert!(
            start.elapsed() < Duration::from_secs(60),
            "jobs still queued after 60 s:\n{queued}"
        );
        std::thread::sleep(Duration::from_millis(300));
    }
    let merge_state = output(
        Command::new("scontrol")
            .env("SLURM_CONF", &conf)
            .args(["show", "job", &merge_job]),
    )
    .unwrap_or_default();
    assert!(
        merge_state.contains("JobState=COMPLETED"),
        "the merge job did not complete:\n{merge_state}"
    );
    drop(daemons);
    let direct = dir.join("direct.png");
    let status = Command::new(SCNC)
        .arg("render")
        .arg(&scene)
        .args(RENDER_ARGS.split(' '))
        .arg("-o")
        .arg(&direct)
        .stdout(Stdio::null())
        .status()
        .expect("scnc runs");
    assert!(status.success());
    let merged = std::fs::read(out.join("final.png")).expect("the merge job wrote final.png");
    let single = std::fs::read(&direct).expect("direct render");
    assert!(
        merged == single,
        "the Slurm-merged image differs from one render"
    );
    for k in 0..TILES {
        assert!(
            out.join(format!("part_{k}.exr")).is_file(),
            "tile {k} missing"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}
