//! `picomis-sim serve`: the real binary on 127.0.0.1 and a free port, sent raw HTTP requests,
//! including every way of escaping the served folder we could think of. Every request has a
//! timeout; the server is killed at the end.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{SocketAddr, TcpStream};
use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::Duration;

const SECRET: &str = "secret outside the folder";

struct Server {
    child: Child,
    addr: SocketAddr,
}

impl Drop for Server {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn start(dir: &Path) -> Server {
    let mut command = Command::new(env!("CARGO_BIN_EXE_picomis-sim"));
    command.args(["serve", "--port", "0", "--dir"]).arg(dir);
    start_command(command)
}

/// Starts `command` (a `serve`) and reads the address it prints.
fn start_command(mut command: Command) -> Server {
    let mut child = command.stdout(Stdio::piped()).stderr(Stdio::null()).spawn().unwrap();
    let mut line = String::new();
    BufReader::new(child.stdout.take().unwrap()).read_line(&mut line).unwrap();
    // "serving <dir or the built-in page> at http://127.0.0.1:PORT/ (Ctrl-C to stop)"
    let url = line.split(" at http://").nth(1).and_then(|s| s.split('/').next()).expect(&line);
    let addr: SocketAddr = url.parse().expect(&line);
    assert!(addr.ip().is_loopback(), "listens on 127.0.0.1 by default: {line}");
    Server { child, addr }
}

/// Sends `request` verbatim; returns (status, headers, body).
fn raw(addr: SocketAddr, request: &[u8]) -> (u16, String, Vec<u8>) {
    let mut s = TcpStream::connect_timeout(&addr, Duration::from_secs(5)).unwrap();
    s.set_read_timeout(Some(Duration::from_secs(10))).unwrap();
    s.set_write_timeout(Some(Duration::from_secs(10))).unwrap();
    let _ = s.write_all(request);
    let mut out = Vec::new();
    let _ = s.take(1 << 24).read_to_end(&mut out);
    let split = out.windows(4).position(|w| w == b"\r\n\r\n").expect("a response head");
    let head = String::from_utf8(out[..split].to_vec()).unwrap();
    let status = head.split(' ').nth(1).unwrap().parse().unwrap();
    (status, head, out[split + 4..].to_vec())
}

fn get(addr: SocketAddr, target: &str) -> (u16, String, Vec<u8>) {
    raw(addr, format!("GET {target} HTTP/1.1\r\nHost: localhost\r\n\r\n").as_bytes())
}

fn site() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let root = dir.path().join("web");
    std::fs::create_dir_all(root.join("sub")).unwrap();
    std::fs::write(root.join("index.html"), "<!doctype html><p>page</p>").unwrap();
    std::fs::write(root.join("main.js"), "'use strict';").unwrap();
    std::fs::write(root.join("style.css"), "p {}").unwrap();
    std::fs::write(root.join("picomis.wasm"), b"\0asm\x01\0\0\0").unwrap();
    std::fs::write(root.join("sub/worker.js"), "1").unwrap();
    std::fs::write(root.join("Cargo.toml"), "[package]").unwrap();
    std::fs::write(dir.path().join("secret.txt"), SECRET).unwrap();
    std::os::unix::fs::symlink(dir.path().join("secret.txt"), root.join("link.txt")).unwrap();
    std::os::unix::fs::symlink(dir.path(), root.join("parent")).unwrap();
    dir
}

#[test]
fn serves_the_page_with_content_types() {
    let dir = site();
    let server = start(&dir.path().join("web"));
    for (target, ctype, body) in [
        ("/", "text/html; charset=utf-8", &b"<!doctype html><p>page</p>"[..]),
        ("/index.html?scene=veach_mis&spp=8", "text/html; charset=utf-8", b"<!doctype html><p>page</p>"),
        ("/main.js", "text/javascript; charset=utf-8", b"'use strict';"),
        ("/style.css", "text/css; charset=utf-8", b"p {}"),
        ("/picomis.wasm", "application/wasm", b"\0asm\x01\0\0\0"),
        ("/sub/worker.js", "text/javascript; charset=utf-8", b"1"),
    ] {
        let (status, head, got) = get(server.addr, target);
        assert_eq!(status, 200, "{target}: {head}");
        assert!(head.contains(&format!("\r\nContent-Type: {ctype}\r\n")), "{target}: {head}");
        assert!(head.contains(&format!("\r\nContent-Length: {}\r\n", body.len())), "{target}: {head}");
        assert_eq!(got, body, "{target}");
    }
    let (status, head, body) = raw(server.addr, b"HEAD /picomis.wasm HTTP/1.0\r\n\r\n");
    assert_eq!((status, body.len()), (200, 0), "{head}");
    assert!(head.contains("Content-Length: 8"), "{head}");
}

#[test]
fn never_serves_anything_outside_the_page() {
    let dir = site();
    let server = start(&dir.path().join("web"));
    let outside = dir.path().join("secret.txt");
    let absolute = format!("/{}", outside.display());
    let targets = [
        "/../secret.txt",
        "/sub/../../secret.txt",
        "/%2e%2e/secret.txt",
        "/%2E%2E/secret.txt",
        "/.%2e/secret.txt",
        "/%2e%2e%2fsecret.txt",
        "/..%2Fsecret.txt",
        "/sub/%2e%2e%2f%2e%2e%2fsecret.txt",
        "/%252e%252e/secret.txt",
        "/..\\secret.txt",
        "/..%5csecret.txt",
        "/%c0%ae%c0%ae/secret.txt",
        &absolute,
        "//secret.txt",
        "/link.txt",
        "/parent/secret.txt",
        "/parent/web/index.html",
        "/sub",
        "/sub/",
        "/Cargo.toml",
        "/secret.txt%00.html",
        "http://localhost/../secret.txt",
        "../secret.txt",
        "*",
    ];
    for target in targets {
        let (status, head, body) = get(server.addr, target);
        assert!([400, 403, 404].contains(&status), "{target}: {head}");
        let body = String::from_utf8_lossy(&body);
        assert!(!body.contains(SECRET) && !body.contains("<p>page"), "{target}: {body}");
    }
}

#[test]
fn rejects_other_methods_and_bad_requests() {
    let dir = site();
    let server = start(&dir.path().join("web"));
    assert_eq!(raw(server.addr, b"POST / HTTP/1.1\r\nContent-Length: 0\r\n\r\n").0, 405);
    assert_eq!(raw(server.addr, b"PUT /x.html HTTP/1.1\r\n\r\n").0, 405);
    assert_eq!(raw(server.addr, b"GET / SPDY/3\r\n\r\n").0, 400);
    assert_eq!(raw(server.addr, b"GET /\r\n\r\n").0, 400);
    assert_eq!(raw(server.addr, b"\r\n\r\n").0, 400);
    // A head longer than the limit is cut off, not buffered.
    let long = format!("GET /{} HTTP/1.1\r\n\r\n", "a".repeat(64 * 1024));
    assert_eq!(raw(server.addr, long.as_bytes()).0, 400);
    let many = format!("GET / HTTP/1.1\r\n{}\r\n", "X: y\r\n".repeat(4000));
    assert_eq!(raw(server.addr, many.as_bytes()).0, 400);
    // The server is still there.
    assert_eq!(get(server.addr, "/").0, 200);
}

#[test]
fn refuses_to_start_without_the_wasm() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("index.html"), "x").unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_picomis-sim"))
        .args(["serve", "--port", "0", "--dir"])
        .arg(dir.path())
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(stderr.contains("picomis.wasm: missing") && stderr.contains("scripts/web.sh build"), "{stderr}");
}

/// `picomis-sim serve` with no `--dir`, from a copy of the binary in a folder of its own (as
/// installed, nowhere near the source tree): the page built into it, with its WebAssembly.
#[test]
fn an_installed_binary_serves_the_page_built_into_it() {
    let dir = tempfile::tempdir().unwrap();
    let bin = dir.path().join("bin");
    std::fs::create_dir(&bin).unwrap();
    let installed = bin.join("picomis-sim");
    std::fs::copy(env!("CARGO_BIN_EXE_picomis-sim"), &installed).unwrap();
    let mut command = Command::new(&installed);
    command.args(["serve", "--port", "0"]).current_dir(dir.path());
    let Ok(wasm) = picomis_sim::page::wasm() else {
        // Built without the wasm32-unknown-unknown target: one line saying how to get it.
        let out = command.output().unwrap();
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{stderr}");
        assert!(stderr.contains("rustup target add wasm32-unknown-unknown"), "{stderr}");
        assert_eq!(stderr.lines().count(), 1, "{stderr}");
        return;
    };
    assert!(wasm.starts_with(b"\0asm"), "a WebAssembly module");
    let server = start_command(command);
    let web = Path::new(env!("CARGO_MANIFEST_DIR")).join("../web");
    for (target, file, ctype) in [
        ("/", "index.html", "text/html; charset=utf-8"),
        ("/index.html?scene=veach_mis", "index.html", "text/html; charset=utf-8"),
        ("/main.js", "main.js", "text/javascript; charset=utf-8"),
        ("/worker.js", "worker.js", "text/javascript; charset=utf-8"),
        ("/style.css", "style.css", "text/css; charset=utf-8"),
    ] {
        let (status, head, body) = get(server.addr, target);
        assert_eq!(status, 200, "{target}: {head}");
        assert!(head.contains(&format!("\r\nContent-Type: {ctype}\r\n")), "{target}: {head}");
        assert_eq!(body, std::fs::read(web.join(file)).unwrap(), "{target}: the page as web/ holds it");
    }
    let (status, head, body) = get(server.addr, "/picomis.wasm");
    assert_eq!(status, 200, "{head}");
    assert!(head.contains("\r\nContent-Type: application/wasm\r\n"), "{head}");
    assert!(body == wasm, "served {} bytes, built in {} bytes", body.len(), wasm.len());
    for target in
        ["/../Cargo.toml", "/wasm/Cargo.toml", "/%2e%2e/web/index.html", "/.hidden", "/sub/", "/x.html"]
    {
        let (status, head, _) = get(server.addr, target);
        assert!([400, 403, 404].contains(&status), "{target}: {head}");
    }
}

/// The page built into the binary is what `web/` holds: every page file (HTML, scripts, style).
#[test]
fn every_page_file_is_built_in() {
    let web = Path::new(env!("CARGO_MANIFEST_DIR")).join("../web");
    let mut on_disk: Vec<String> = std::fs::read_dir(&web)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| [".html", ".js", ".css"].iter().any(|ext| n.ends_with(ext)))
        .collect();
    on_disk.sort();
    let mut built_in: Vec<String> = picomis_sim::page::FILES.iter().map(|(n, _)| n.to_string()).collect();
    built_in.sort();
    assert_eq!(built_in, on_disk, "host-sim/src/page.rs: FILES lists web/'s page files");
    for (name, bytes) in picomis_sim::page::FILES {
        assert_eq!(bytes, std::fs::read(web.join(name)).unwrap(), "{name}");
    }
}
