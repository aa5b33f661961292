//! The command line under faults, as a hostile user meets it: input that used to panic or be
//! accepted without a word, outputs that cannot be written, a signal in the middle of a sweep.
//! Every refusal names the option, the value and the rule, and comes before any rendering (no
//! frame time printed) with nothing written earlier lost.

use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

/// Runs `foveate` (validation on) in `dir`: exit success, stdout, stderr.
fn run_in(dir: &Path, args: &[&str]) -> (bool, String, String) {
    let o = Command::new(env!("CARGO_BIN_EXE_foveate"))
        .current_dir(dir)
        .arg("--validation")
        .args(args)
        .output()
        .expect("run foveate");
    let text = |b: &[u8]| String::from_utf8_lossy(b).into_owned();
    (o.status.success(), text(&o.stdout), text(&o.stderr))
}

/// A fresh scratch folder for one test.
fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("foveate-faults-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Refused with `needle` in the error, before anything rendered.
fn refused(dir: &Path, args: &[&str], needle: &str) {
    let (ok, out, err) = run_in(dir, args);
    assert!(!ok, "{args:?} was accepted:\n{out}");
    assert!(
        err.contains(needle),
        "{args:?}: expected `{needle}` in:\n{err}"
    );
    assert!(!err.contains("panicked"), "{args:?} panicked:\n{err}");
    assert!(
        !out.contains("frame time"),
        "{args:?} rendered before refusing:\n{out}"
    );
}

/// A fovea as large as its view (ratio 1 on profiles whose fovea view rounds to the full
/// resolution) renders instead of panicking (exit 101 before the fix).
#[test]
fn a_fovea_as_large_as_the_view_renders() {
    let dir = scratch("ratio-one");
    for (hmd, ratio, res) in [
        ("vive", "1.0", "48"),
        ("rift-cv1", "1.0", "40"),
        ("index", "0.999", "128"),
    ] {
        let args = [
            "render",
            "--hmd",
            hmd,
            "--foveate",
            ratio,
            "--res",
            res,
            "--frames",
            "1",
        ];
        let (ok, _, err) = run_in(&dir, &args);
        assert!(ok, "{args:?}:\n{err}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Input once accepted without a word is an error naming the option, the value and the rule;
/// negative numbers parse as written.
#[test]
fn silent_acceptance_is_an_error_naming_option_value_and_rule() {
    let dir = scratch("silent");
    let r = ["render", "--res", "32"];
    let with = |extra: &[&'static str]| [&r[..], extra].concat();
    refused(
        &dir,
        &with(&["--foveate", "0.5", "--gaze", "2,0"]),
        "invalid gaze = 2,0: X and Y finite, in -1..1",
    );
    refused(
        &dir,
        &with(&["--foveate", "0.5", "--gaze", "1e30,0"]),
        "invalid gaze = 1000000000000000000000000000000,0",
    );
    refused(
        &dir,
        &["flicker", "--res", "32", "--gaze", "0.3,-1.5"],
        "invalid gaze = 0.3,-1.5: X and Y finite, in -1..1",
    );
    refused(
        &dir,
        &[
            "flicker",
            "--res",
            "32",
            "--temporal",
            "--temporal-msaa",
            "1,2",
        ],
        "invalid periphery_msaa = 2: 1 or 4",
    );
    for (option, value, mode) in [
        ("--temporal-blend", "0.3", "accumulation (--foveate)"),
        (
            "--temporal-neighbourhood",
            "cross",
            "accumulation (--foveate)",
        ),
        (
            "--temporal-new-sample",
            "nearest",
            "accumulation (--foveate)",
        ),
        ("--split", "2px", "--mffr"),
        ("--periphery-density", "0.5", "--foveate"),
        ("--radial-outer", "0.9", "--radial-density"),
    ] {
        let needle =
            format!("invalid {option} = {value}: it sets a parameter of {mode}, which is off");
        refused(&dir, &with(&[option, value]), &needle);
    }
    // Single frames turn accumulation off: its options are refused, and so is asking for both.
    refused(
        &dir,
        &with(&["--foveate", "0.5", "--single-frame", "--temporal-blend", "0.3"]),
        "invalid --temporal-blend = 0.3: it sets a parameter of accumulation, which is off (drop --single-frame",
    );
    refused(
        &dir,
        &with(&["--foveate", "0.5", "--single-frame", "--temporal"]),
        "invalid --temporal with --single-frame",
    );
    for (option, value, needle) in [
        (
            "--temporal-neighbourhood",
            "5x5",
            "invalid clip neighbourhood = 5x5: 3x3 or cross",
        ),
        (
            "--temporal-new-sample",
            "bilinear",
            "invalid new sample = bilinear: nearest or weighted",
        ),
    ] {
        let args = with(&["--foveate", "0.5", "--temporal", option, value]);
        refused(&dir, &args, needle);
    }
    // A negative number is a value, not an option: the range check answers, not the parser.
    refused(&dir, &with(&["--ipd-mm", "-64"]), "invalid ipd = -0.064");
    refused(
        &dir,
        &["xr", "--timeout", "-1"],
        "invalid timeout = -1: a finite number of seconds above 0",
    );
    refused(&dir, &["xr", "--timeout", "NaN"], "invalid timeout = NaN");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Gaze traces that would render as if no trace were given: empty, header only, one usable
/// sample, every sample after the run.
#[test]
fn traces_that_would_go_unused_are_refused() {
    let dir = scratch("traces");
    for (name, text, needle) in [
        ("empty.csv", "", "0 usable samples of 0"),
        (
            "header.csv",
            "time,lx,ly,rx,ry,valid\n",
            "0 usable samples of 0",
        ),
        (
            "one.csv",
            "0,0.1,0.1,0.1,0.1,1\n0.01,NaN,0,0,0,1\n",
            "1 usable samples of 2",
        ),
        (
            "future.csv",
            "100,0,0,0,0,1\n101,0,0,0,0,1\n",
            "its first sample is at 100 s, after the run's last frame",
        ),
    ] {
        std::fs::write(dir.join(name), text).unwrap();
        refused(
            &dir,
            &[
                "render",
                "--res",
                "32",
                "--foveate",
                "0.5",
                "--gaze-trace",
                name,
            ],
            needle,
        );
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Outputs that cannot be written are refused before the render, and a refused run leaves the
/// earlier file byte for byte; the image format follows the extension.
#[test]
fn outputs_are_checked_first_and_written_whole() {
    let dir = scratch("outputs");
    let (ok, _, err) = run_in(
        &dir,
        &[
            "render", "--res", "32", "--frames", "1", "--out", "good.png",
        ],
    );
    assert!(ok, "{err}");
    let good = std::fs::read(dir.join("good.png")).unwrap();
    std::fs::write(dir.join("a-file"), b"x").unwrap();
    let r = ["render", "--res", "32", "--out"];
    refused(
        &dir,
        &[&r[..], &["/proc/x.png"]].concat(),
        "cannot write /proc/x.png",
    );
    refused(
        &dir,
        &[&r[..], &["a-file/x.png"]].concat(),
        "a-file is not a folder",
    );
    refused(&dir, &[&r[..], &["."]].concat(), "it is a folder");
    refused(
        &dir,
        &[&r[..], &["x.bmp"]].concat(),
        "its extension names no format foveate writes (bmp)",
    );
    refused(
        &dir,
        &[
            "render", "--res", "32", "--out", "good.png", "--gaze", "5,0",
        ],
        "invalid gaze",
    );
    assert_eq!(
        std::fs::read(dir.join("good.png")).unwrap(),
        good,
        "the earlier file kept"
    );
    refused(
        &dir,
        &["compare", "--res", "32", "--csv", "a-file/t.csv"],
        "a-file is not a folder",
    );
    let (ok, _, err) = run_in(
        &dir,
        &["render", "--res", "32", "--frames", "1", "--out", "x.jpg"],
    );
    assert!(ok, "{err}");
    assert_eq!(
        &std::fs::read(dir.join("x.jpg")).unwrap()[..3],
        [0xff, 0xd8, 0xff],
        "JPEG data"
    );
    let mut names: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(
        names,
        ["a-file", "good.png", "x.jpg"],
        "no temporary file left behind"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A pipeline cache whose path is a folder is not written, and leaves nothing beside it (a
/// `pipelines.tmp<PID>` was left on every run). Each device keeps its own file (its identity
/// in the name): the first run finds the name, the second finds a folder there.
#[test]
fn a_pipeline_cache_that_is_a_folder_leaves_nothing_behind() {
    let dir = scratch("cache");
    std::fs::create_dir_all(dir.join("caches")).unwrap();
    let render = || {
        let o = Command::new(env!("CARGO_BIN_EXE_foveate"))
            .current_dir(&dir)
            .env(
                "FOVEATE_PIPELINE_CACHE",
                dir.join("caches").join("pipelines.bin"),
            )
            .args(["render", "--res", "32", "--frames", "1", "--out", "f.png"])
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    };
    render();
    let written: Vec<_> = std::fs::read_dir(dir.join("caches"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .collect();
    assert_eq!(written.len(), 1, "{written:?}: one file, for this device");
    let name = written[0]
        .file_name()
        .unwrap()
        .to_string_lossy()
        .into_owned();
    assert!(
        name.starts_with("pipelines-") && name.ends_with(".bin") && name.len() > 16,
        "{name}: the device's identity in the name"
    );
    std::fs::remove_file(&written[0]).unwrap();
    std::fs::create_dir(&written[0]).unwrap();
    render();
    let names: Vec<_> = std::fs::read_dir(dir.join("caches"))
        .unwrap()
        .map(|e| e.unwrap().file_name())
        .collect();
    assert_eq!(names.len(), 1, "{names:?}: the cache folder alone");
    assert_eq!(std::fs::read_dir(&written[0]).unwrap().count(), 0);
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A pipeline cache or a gaze trace at a named pipe is neither waited on (opening a pipe
/// waits for a writer) nor replaced by a file: the run ends, the pipe stays a pipe. (A pipe
/// stands for any special file: the test leaves real devices such as `/dev/zero` be.)
#[test]
fn special_files_are_neither_read_nor_replaced() {
    use std::os::unix::fs::FileTypeExt;
    let dir = scratch("special");
    let pipe = dir.join("pipe");
    assert!(Command::new("mkfifo")
        .arg(&pipe)
        .status()
        .unwrap()
        .success());
    let bin = env!("CARGO_BIN_EXE_foveate");
    let o = Command::new("timeout")
        .current_dir(&dir)
        .env("FOVEATE_PIPELINE_CACHE", &pipe)
        .args([
            "60", bin, "render", "--res", "32", "--frames", "1", "--out", "f.png",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let o = Command::new("timeout")
        .current_dir(&dir)
        .args([
            "60",
            bin,
            "render",
            "--res",
            "32",
            "--foveate",
            "0.5",
            "--gaze-trace",
            "pipe",
        ])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(err.contains("pipe is not a regular file"), "{err}");
    assert!(
        std::fs::metadata(&pipe).unwrap().file_type().is_fifo(),
        "still a pipe"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// `foveate` started in `dir`, its stdout and stderr piped; with `logged`, its progress logged
/// to stderr (read it as it runs: a full pipe would stall it).
fn spawn_in(dir: &Path, args: &[&str], logged: bool) -> std::process::Child {
    let log = if logged { "foveate=info" } else { "warn" };
    Command::new(env!("CARGO_BIN_EXE_foveate"))
        .current_dir(dir)
        .env("RUST_LOG", log)
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap()
}

/// Ctrl-C, as a user at the terminal sends it.
fn sigint(child: &std::process::Child) {
    let pid = child.id().to_string();
    assert!(Command::new("kill")
        .args(["-INT", &pid])
        .status()
        .unwrap()
        .success());
}

/// SIGINT in the middle of `compare` (once two configurations are judged) stops it after the
/// row in hand: it exits non-zero saying so, and its CSV holds the rows finished, whole.
/// Negative control: without the handler the signal kills it and no CSV exists.
#[test]
fn sigint_during_compare_writes_the_rows_done() {
    let dir = scratch("sigint");
    let mut child = spawn_in(
        &dir,
        &[
            "compare", "--res", "384", "--frames", "2", "--csv", "rows.csv",
        ],
        true,
    );
    let mut log = String::new();
    for line in BufReader::new(child.stderr.take().unwrap()).lines() {
        let line = line.unwrap();
        log += &line;
        log.push('\n');
        if line.contains("compare: judged 2 of") {
            sigint(&child);
        }
    }
    let status = child.wait().unwrap();
    assert!(!status.success(), "{log}");
    assert!(
        log.contains("interrupted (Ctrl-C or SIGTERM): compare stopped after judging"),
        "{log}"
    );
    let mut reader = csv::Reader::from_path(dir.join("rows.csv")).expect("the CSV of rows done");
    let rows = reader.records().collect::<Result<Vec<_>, _>>().unwrap();
    // Judged: the reference and at least one configuration; stopped before the last of 8.
    assert!((1..8).contains(&rows.len()), "{} rows\n{log}", rows.len());
    std::fs::remove_dir_all(&dir).unwrap();
}

/// SIGINT as `flicker --pareto` starts its first motion stops it with nothing measured: it
/// says so, and plots no empty frontier. Mutation: plotting every motion asked for leaves
/// empty plots behind.
#[test]
fn sigint_during_flicker_plots_no_empty_frontier() {
    let dir = scratch("sigint-flicker");
    let mut child = spawn_in(
        &dir,
        &[
            "flicker",
            "--res",
            "96",
            "--ratios",
            "0.5",
            "--flip",
            "--motions",
            "still,walking",
            "--pareto",
            "frontier",
        ],
        false,
    );
    let mut out = String::new();
    for line in BufReader::new(child.stdout.take().unwrap()).lines() {
        let line = line.unwrap();
        if line.starts_with("device:") {
            sigint(&child);
        }
        out += &line;
        out.push('\n');
    }
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success(), "{out}");
    assert!(
        err.contains("flicker stopped during a motion; the 0 motions finished"),
        "{err}"
    );
    let written: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert!(written.is_empty(), "{written:?}\n{out}");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A device lost in the middle of `flicker` (`FOVEATE_LOSE_DEVICE_AFTER_SUBMITS`, the gpu
/// module's fault seam, placed a few submissions into the second motion: the first motion's
/// count read from a run of it alone) ends the run with an error naming the loss and the motion,
/// no panic, and the first motion's rows printed and in the CSV, whole. Negative control (run):
/// with the motion's failure propagated at once, no CSV is written.
#[test]
fn a_device_lost_during_flicker_leaves_the_motions_done_written() {
    const SEAM: &str = "FOVEATE_LOSE_DEVICE_AFTER_SUBMITS";
    let dir = scratch("lost");
    let flicker = |motions: &str, lose_at: u64| {
        Command::new(env!("CARGO_BIN_EXE_foveate"))
            .current_dir(&dir)
            .env(SEAM, lose_at.to_string())
            .env("RUST_LOG", "foveate::gpu=debug")
            .args(["flicker", "--res", "96", "--ratios", "0.5", "--frames", "4"])
            .args(["--motions", motions, "--csv", "rows.csv"])
            .output()
            .unwrap()
    };
    let alone = flicker("still", u64::MAX);
    let log = String::from_utf8_lossy(&alone.stderr);
    assert!(alone.status.success(), "{log}");
    let first_motion: u64 = (log.lines())
        .filter_map(|l| l.split(": submission ").nth(1))
        .filter_map(|rest| rest.split(' ').next()?.parse().ok())
        .max()
        .expect("the seam counts submissions");
    std::fs::remove_file(dir.join("rows.csv")).unwrap();

    let lost = flicker("still,walking", first_motion + 3);
    let err = String::from_utf8_lossy(&lost.stderr);
    assert!(!lost.status.success(), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    assert!(err.contains("VK_ERROR_DEVICE_LOST"), "{err}");
    assert!(
        err.contains("the 1 motions finished before it are in the table above and the CSV")
            && err.contains("walking motion failed"),
        "{err}"
    );
    let mut reader = csv::Reader::from_path(dir.join("rows.csv")).expect("the first motion's CSV");
    let rows = reader.records().collect::<Result<Vec<_>, _>>().unwrap();
    assert!(
        !rows.is_empty() && rows.iter().all(|r| &r[0] == "still"),
        "{rows:?}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

/// A scene whose buffer is a sparse 4 GB file declared as 36 bytes is refused by `plan` within
/// 100 MB of address space (`ulimit -v`), naming the buffer and both sizes: it is refused from
/// its size, before a byte is read, and before the device starts. Negative control: a loader
/// that reads the file whole aborts on the allocation instead.
#[test]
fn a_huge_buffer_is_refused_within_100_mb() {
    let dir = scratch("huge");
    let gltf = r#"{"asset": {"version": "2.0"}, "buffers": [{"uri": "big.bin", "byteLength": 36}],
                   "scenes": [{"nodes": []}], "scene": 0}"#;
    std::fs::write(dir.join("evil.gltf"), gltf).unwrap();
    std::fs::File::create(dir.join("big.bin"))
        .unwrap()
        .set_len(4 << 30)
        .unwrap();
    let o = Command::new("sh")
        .current_dir(&dir)
        .args([
            "-c",
            "ulimit -v 102400 && exec \"$0\" plan --scene evil.gltf",
        ])
        .arg(env!("CARGO_BIN_EXE_foveate"))
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(!o.status.success());
    assert!(
        err.contains("buffer 0:") && err.contains("holds 4294967296 bytes, more than the 36"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).unwrap();
}
