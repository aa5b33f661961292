//! `foveate view` as a person sees it: under Xvfb with lavapipe, the window is resized mid-run,
//! the mouse moves the gaze, the window's pixels are grabbed with `xwd` and compared with the
//! image the viewer says it presented and with `foveate render` of the same frame offscreen.
//! Validation is on throughout (the viewer fails on any message).

use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};
use std::thread::sleep;
use std::time::{Duration, Instant};

use foveate_tests::Xvfb;
use image::RgbaImage;

/// An `xwd` dump (X11 window dump, ZPixmap, 24/32 bits per pixel) as RGBA.
fn parse_xwd(bytes: &[u8]) -> RgbaImage {
    let field = |i: usize| u32::from_be_bytes(bytes[4 * i..4 * i + 4].try_into().unwrap());
    let (header_size, width, height) = (field(0) as usize, field(4), field(5));
    let (byte_order, bits_per_pixel, bytes_per_line) = (field(7), field(11), field(12) as usize);
    let (red_mask, green_mask, blue_mask) = (field(14), field(15), field(16));
    // ncolors: the colour entries (12 bytes each) written between header and pixels.
    let colormap_entries = field(19) as usize;
    assert_eq!(field(2), 2, "ZPixmap");
    assert_eq!(bits_per_pixel, 32, "32 bits per pixel");
    let pixels = &bytes[header_size + 12 * colormap_entries..];
    let channel = |p: u32, mask: u32| ((p & mask) >> mask.trailing_zeros()) as u8;
    let mut image = RgbaImage::new(width, height);
    for y in 0..height {
        for x in 0..width {
            let at = y as usize * bytes_per_line + 4 * x as usize;
            let raw: [u8; 4] = pixels[at..at + 4].try_into().unwrap();
            let p = if byte_order == 0 {
                u32::from_le_bytes(raw)
            } else {
                u32::from_be_bytes(raw)
            };
            image.put_pixel(
                x,
                y,
                image::Rgba([
                    channel(p, red_mask),
                    channel(p, green_mask),
                    channel(p, blue_mask),
                    255,
                ]),
            );
        }
    }
    image
}

/// Largest difference of any channel (alpha aside) between two images of one size.
fn max_difference(a: &RgbaImage, b: &RgbaImage) -> u8 {
    assert_eq!(a.dimensions(), b.dimensions());
    a.pixels()
        .zip(b.pixels())
        .flat_map(|(p, q)| (0..3).map(move |c| p[c].abs_diff(q[c])))
        .max()
        .unwrap_or(0)
}

/// `foveate render` of [`FRAME`] with `extra` options, one frame, written to and read from
/// `path`.
fn render_offscreen(path: &Path, extra: &[&str]) -> RgbaImage {
    let mut args = vec!["--validation", "render"];
    args.extend(FRAME);
    args.extend(extra);
    args.extend(["--frames", "1", "--out", path.to_str().unwrap()]);
    let out = Command::new(env!("CARGO_BIN_EXE_foveate"))
        .args(&args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    image::open(path).unwrap().into_rgba8()
}

const FRAME: &[&str] = &[
    "--res",
    "64",
    "--foveate",
    "0.35",
    "--single-frame",
    "--tint",
    "--msaa",
    "1",
];

/// The viewer, resized and with the mouse moved, shows exactly what it says it presented, and
/// that is the offscreen render of the same configuration at the gaze under the mouse.
/// Mutations: the blit's eyes swapped, off by a pixel or scaled (the final window is 1:1), or
/// the mouse-to-gaze map off, each fails a comparison; a validation message fails the run.
#[test]
fn the_window_shows_the_offscreen_frame_at_the_mouse_gaze() {
    let dir = std::env::temp_dir().join(format!("foveate-view-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let saved = dir.join("presented.png");
    let x = Xvfb::start();
    let mut args = vec!["--validation", "view"];
    args.extend(FRAME);
    args.extend([
        "--window",
        "128x64",
        "--frames",
        "100000",
        "--save",
        saved.to_str().unwrap(),
    ]);
    let mut viewer = Command::new(env!("CARGO_BIN_EXE_foveate"))
        .args(&args)
        .env("DISPLAY", &x.display)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let window = x.run("xdotool", &["search", "--sync", "--name", "foveate view"]);
    let window = window
        .lines()
        .next()
        .expect("the viewer's window")
        .to_string();
    // Mid-run: the mouse over the right eye, a resize that scales the eyes, and back to 1:1.
    sleep(Duration::from_millis(500));
    x.run("xdotool", &["mousemove", "--window", &window, "100", "40"]);
    x.run("xdotool", &["windowsize", &window, "300", "200"]);
    sleep(Duration::from_millis(800));
    x.run("xdotool", &["windowsize", &window, "128", "64"]);
    sleep(Duration::from_millis(800));
    // The gaze (0.5, 0.5): three quarters across the left eye, a quarter down.
    x.run("xdotool", &["mousemove", "--window", &window, "48", "16"]);
    sleep(Duration::from_millis(1500));
    let dump = Command::new("xwd")
        .args(["-silent", "-id", &window])
        .env("DISPLAY", &x.display)
        .output()
        .expect("xwd (apt x11-apps)");
    assert!(dump.status.success(), "xwd failed");
    // Real key events (XTEST) go to the focused window; there is no window manager to focus it.
    x.run("xdotool", &["windowfocus", "--sync", &window]);
    x.run("xdotool", &["key", "q"]);
    let started = Instant::now();
    let status = loop {
        if let Some(status) = viewer.try_wait().unwrap() {
            break status;
        }
        assert!(
            started.elapsed() < Duration::from_secs(60),
            "the viewer did not quit"
        );
        sleep(Duration::from_millis(50));
    };
    let mut out = String::new();
    viewer
        .stdout
        .take()
        .unwrap()
        .read_to_string(&mut out)
        .unwrap();
    let mut err = String::new();
    viewer
        .stderr
        .take()
        .unwrap()
        .read_to_string(&mut err)
        .unwrap();
    assert!(status.success(), "viewer failed:\n{out}\n{err}");
    assert!(out.contains("saved "), "{out}");

    let grabbed = parse_xwd(&dump.stdout);
    let presented = image::open(&saved).unwrap().into_rgba8();
    assert_eq!(grabbed.dimensions(), (128, 64));
    assert_eq!(
        max_difference(&grabbed, &presented),
        0,
        "the window shows what the viewer presented"
    );

    let offscreen = render_offscreen(&dir.join("offscreen.png"), &["--gaze", "0.5,0.5"]);
    assert_eq!(
        max_difference(&grabbed, &offscreen),
        0,
        "the window shows the offscreen frame at the gaze under the mouse"
    );
    // The gaze reached the frame: the same frame at the centre gaze differs.
    let centred = render_offscreen(&dir.join("centre.png"), &[]);
    assert!(
        max_difference(&grabbed, &centred) > 50,
        "the mouse moved the gaze"
    );
    std::fs::remove_dir_all(Path::new(&dir)).unwrap();
}

/// `--judge N` judges the first presented frame and every Nth after it against the
/// full-quality reference, validation clean, and says each judgement's figures and time (the
/// judgement itself is held to its reference in the library's tests: here the cadence, the
/// line, and that judging between frames breaks nothing).
#[test]
fn the_viewer_judges_every_nth_frame() {
    let x = Xvfb::start();
    let mut args = vec!["--validation", "view"];
    args.extend(FRAME);
    args.extend(["--window", "128x64", "--frames", "7", "--judge", "3"]);
    let out = Command::new(env!("CARGO_BIN_EXE_foveate"))
        .args(&args)
        .env("DISPLAY", &x.display)
        .output()
        .unwrap();
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{stdout}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let judged: Vec<&str> = stdout
        .lines()
        .filter(|l| l.starts_with("judge: eFLIP p99 fovea "))
        .collect();
    // Frames 1, 4 and 7.
    assert_eq!(judged.len(), 3, "{stdout}");
    assert!(
        judged
            .iter()
            .all(|l| l.contains("apart from the frame times")),
        "{stdout}"
    );
}
