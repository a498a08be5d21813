//! `picomis-sim view` in a real window (feature `window`; needs Xvfb and ImageMagick's `import`,
//! which `scripts/test.sh` installs). A virtual X screen exactly the window's size holds the
//! window at (0, 0); after N passes a screenshot of the screen must show, pixel for pixel, the
//! Rgb565 framebuffer that `picomis-sim render --spp 2^(N-1) --out F.rgb565` writes, converted
//! to 8-bit RGB the way the simulator converts it and magnified by `--scale`. The simulator's own
//! dump (`EG_SIMULATOR_DUMP`) is checked the same way.
//!
//! The screenshot is kept as `target/tmp/view_window.png` (the README's `docs/view_window.png`).
#![cfg(feature = "window")]

mod common;

use std::io::{BufRead, BufReader, Read};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

use embedded_graphics_core::pixelcolor::raw::RawU16;
use embedded_graphics_core::pixelcolor::{Rgb565, Rgb888, RgbColor};
use picomis_sim::view::{DEVICE_HEIGHT, DEVICE_WIDTH, STATUS_HEIGHT};

const SCALE: u32 = 2;
const PASSES: u32 = 6;
const SPP: u32 = 1 << (PASSES - 1);

/// Kills a child process we started when dropped (also when an assertion fails).
struct Killed(Child);

impl Drop for Killed {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

/// An RGB image.
struct Rgb {
    width: u32,
    height: u32,
    data: Vec<[u8; 3]>,
}

fn read_png(path: &Path) -> Rgb {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    let channels = match info.color_type {
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        other => panic!("{}: unexpected PNG colour type {other:?}", path.display()),
    };
    assert_eq!(info.bit_depth, png::BitDepth::Eight, "{}", path.display());
    let data = buf[..info.buffer_size()].chunks(channels).map(|p| [p[0], p[1], p[2]]).collect();
    Rgb { width: info.width, height: info.height, data }
}

/// `picomis-sim render` of the default scene at the device's size as an Rgb565 framebuffer,
/// converted to 8-bit RGB as the simulator does (`Rgb888::from(Rgb565)`).
fn expected(dir: &Path) -> Vec<[u8; 3]> {
    let (w, h, spp) = (DEVICE_WIDTH.to_string(), DEVICE_HEIGHT.to_string(), SPP.to_string());
    common::run_ok(dir, &["render", "--spp", &spp, "--width", &w, "--height", &h, "--out", "ref.rgb565"]);
    let bytes = std::fs::read(dir.join("ref.rgb565")).unwrap();
    assert_eq!(bytes.len() as u32, DEVICE_WIDTH * DEVICE_HEIGHT * 2);
    bytes
        .chunks(2)
        .map(|b| {
            let c: Rgb888 = Rgb565::from(RawU16::new(u16::from_le_bytes([b[0], b[1]]))).into();
            [c.r(), c.g(), c.b()]
        })
        .collect()
}

/// Pixels of the film area of `shot` (magnified by SCALE) that differ from `expected`.
fn differences(shot: &Rgb, expected: &[[u8; 3]]) -> usize {
    let mut bad = 0;
    for y in 0..DEVICE_HEIGHT * SCALE {
        for x in 0..DEVICE_WIDTH * SCALE {
            let want = expected[((y / SCALE) * DEVICE_WIDTH + x / SCALE) as usize];
            if shot.data[(y * shot.width + x) as usize] != want {
                bad += 1;
            }
        }
    }
    bad
}

fn window_size() -> (u32, u32) {
    (DEVICE_WIDTH * SCALE, (DEVICE_HEIGHT + STATUS_HEIGHT) * SCALE)
}

fn view(dir: &Path) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_picomis-sim"));
    c.args(["view", "--passes", &PASSES.to_string(), "--scale", &SCALE.to_string()]).current_dir(dir);
    c
}

/// Starts Xvfb with a screen of `w` x `h` on a free display; returns it and the display name.
fn xvfb(w: u32, h: u32) -> (Killed, String) {
    let mut child = Command::new("Xvfb")
        .args(["-displayfd", "1", "-screen", "0", &format!("{w}x{h}x24"), "-nolisten", "tcp"])
        .stdout(Stdio::piped())
        .stderr(Stdio::null())
        .spawn()
        .expect("Xvfb is not installed (Debian: apt-get install xvfb; scripts/test.sh installs it)");
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap()).read_line(&mut line).unwrap();
    let number: u32 = line.trim().parse().unwrap_or_else(|_| panic!("Xvfb printed {line:?}"));
    (Killed(child), format!(":{number}"))
}

/// Waits for a line of `child`'s stdout that starts with `prefix`.
fn wait_for_line(child: &mut Child, prefix: &str, timeout: Duration) -> Vec<String> {
    let stdout = child.stdout.take().unwrap();
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            if tx.send(line).is_err() {
                break;
            }
        }
    });
    let start = Instant::now();
    let mut seen = Vec::new();
    while start.elapsed() < timeout {
        match rx.recv_timeout(Duration::from_millis(100)) {
            Ok(line) => {
                let done = line.starts_with(prefix);
                seen.push(line);
                if done {
                    return seen;
                }
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {
                if let Ok(Some(status)) = child.try_wait() {
                    let mut err = String::new();
                    if let Some(mut e) = child.stderr.take() {
                        let _ = e.read_to_string(&mut err);
                    }
                    panic!("view exited with {status} before {prefix:?}: {seen:?} {err}");
                }
            }
            Err(mpsc::RecvTimeoutError::Disconnected) => break,
        }
    }
    panic!("no line {prefix:?} within {timeout:?}: {seen:?}");
}

fn screenshot(display: &str, out: &Path) -> Rgb {
    let status = Command::new("import")
        .args(["-display", display, "-window", "root"])
        .arg(format!("png24:{}", out.display()))
        .status()
        .expect("ImageMagick's import is not installed (Debian: apt-get install imagemagick)");
    assert!(status.success(), "import failed");
    read_png(out)
}

#[test]
fn the_window_shows_the_firmware_framebuffer_pixel_for_pixel() {
    let dir = tempfile::tempdir().unwrap();
    let expected = expected(dir.path());
    let (w, h) = window_size();
    let (_xvfb, display) = xvfb(w, h);
    let child = view(dir.path())
        .env("DISPLAY", &display)
        .env("SDL_VIDEODRIVER", "x11")
        .env_remove("EG_SIMULATOR_DUMP")
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let mut child = Killed(child);
    let lines = wait_for_line(&mut child.0, &format!("pass {PASSES}:"), Duration::from_secs(300));
    eprintln!("{}", lines.join("\n"));
    assert!(lines.last().unwrap().contains(&format!("{SPP} spp")), "{lines:?}");

    let shot_path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("view_window.png");
    // The X server may show the last frame a moment after the line: retry for a few seconds.
    let start = Instant::now();
    let (shot, bad) = loop {
        let shot = screenshot(&display, &shot_path);
        assert_eq!((shot.width, shot.height), (w, h), "screen size");
        let bad = differences(&shot, &expected);
        if bad == 0 || start.elapsed() > Duration::from_secs(10) {
            break (shot, bad);
        }
        std::thread::sleep(Duration::from_millis(250));
    };
    eprintln!(
        "screenshot {} ({w}x{h}): {bad} of {} film pixels differ",
        shot_path.display(),
        w * DEVICE_HEIGHT * SCALE
    );
    assert_eq!(bad, 0, "the window differs from `render --out F.rgb565`");
    // The status bar is drawn (text: more than one colour under the image).
    let status: std::collections::HashSet<[u8; 3]> =
        shot.data[(DEVICE_HEIGHT * SCALE * w) as usize..].iter().copied().collect();
    assert!(status.len() > 1, "no status line");
    // The check can fail: the image of another spp differs.
    let dir2 = tempfile::tempdir().unwrap();
    let other = {
        let (w, h) = (DEVICE_WIDTH.to_string(), DEVICE_HEIGHT.to_string());
        common::run_ok(
            dir2.path(),
            &["render", "--spp", "1", "--width", &w, "--height", &h, "--out", "one.rgb565"],
        );
        let bytes = std::fs::read(dir2.path().join("one.rgb565")).unwrap();
        bytes
            .chunks(2)
            .map(|b| {
                let c: Rgb888 = Rgb565::from(RawU16::new(u16::from_le_bytes([b[0], b[1]]))).into();
                [c.r(), c.g(), c.b()]
            })
            .collect::<Vec<_>>()
    };
    assert!(differences(&shot, &other) > 1000, "a 1 spp image would pass too");
}

#[test]
fn the_simulators_own_dump_matches_too() {
    let dir = tempfile::tempdir().unwrap();
    let expected = expected(dir.path());
    // With EG_SIMULATOR_DUMP the simulator writes the display after the last pass and exits,
    // without opening a window.
    let out = view(dir.path()).env("EG_SIMULATOR_DUMP", "dump.png").env_remove("DISPLAY").output().unwrap();
    assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
    let dump = read_png(&dir.path().join("dump.png"));
    assert_eq!((dump.width, dump.height), window_size());
    assert_eq!(differences(&dump, &expected), 0, "the simulator's dump differs from `render --out F.rgb565`");
}
