//! `picomis-sim serve`: serves the browser page on a local port, because browsers do not load
//! WebAssembly from `file://`. The page is the one built into the binary ([`crate::page`]), or
//! with `--dir` a folder (`web/` while developing the page).
//!
//! A deliberately small static file server on `std::net`: GET and HEAD only, one request per
//! connection, bounded request size and socket timeouts, no directory listing. Every request
//! target goes through [`request_path`], the one function that decides which names a request
//! may ask for: a `/`-separated list of plain names, never a path that leaves the page (`..`,
//! encoded or not, absolute, backslashes, hidden names). The built-in page then answers only
//! its own file names ([`built_in`]); a folder only regular files of known page types inside it,
//! never through a symlink ([`resolve`]).

use std::borrow::Cow;
use std::io::{BufRead, BufReader, Read, Write};
use std::net::{IpAddr, Ipv4Addr, SocketAddr, TcpListener, TcpStream};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use crate::SimError;
use crate::page;
pub use crate::page::WASM_FILE;

/// How to build [`WASM_FILE`] into a folder, for the error message when it is missing there.
pub const BUILD_HINT: &str = "scripts/web.sh build";

/// Longest request head (request line and headers) read, in bytes.
pub const MAX_REQUEST: usize = 8 * 1024;

/// Largest file served, in bytes.
pub const MAX_FILE: u64 = 64 << 20;

/// Connections handled at once; more are closed at once.
pub const MAX_CONNECTIONS: usize = 32;

const TIMEOUT: Duration = Duration::from_secs(10);

/// `picomis-sim serve`.
#[derive(Debug, clap::Args)]
pub struct ServeArgs {
    /// TCP port (0: any free port; the address is printed).
    #[arg(long, default_value_t = 8000)]
    pub port: u16,
    /// Address to listen on (e.g. 0.0.0.0 for every interface).
    #[arg(long, value_name = "ADDR", default_value_t = IpAddr::V4(Ipv4Addr::LOCALHOST))]
    pub bind: IpAddr,
    /// Serve this folder instead of the page built into picomis-sim (to develop the page:
    /// `web`, after `scripts/web.sh build` has written web/picomis.wasm).
    #[arg(long, value_name = "DIR")]
    pub dir: Option<PathBuf>,
}

/// What `serve` serves.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Site {
    /// The page built into this binary ([`crate::page`]).
    BuiltIn,
    /// A folder, by its canonical path.
    Folder(PathBuf),
}

impl Site {
    /// The site of `--dir`: the folder, which must hold [`WASM_FILE`]; without `--dir` the
    /// built-in page, which must have its WebAssembly.
    pub fn of(dir: Option<&Path>) -> Result<Site, SimError> {
        let Some(dir) = dir else {
            return match page::wasm() {
                Ok(_) => Ok(Site::BuiltIn),
                Err(why) => Err(SimError::Usage(format!(
                    "this picomis-sim has no WebAssembly for the page: {why} (or serve a folder \
                     holding {WASM_FILE} with --dir; `{BUILD_HINT}` writes web/{WASM_FILE})"
                ))),
            };
        };
        let root =
            dir.canonicalize().map_err(|e| SimError::Usage(format!("--dir {}: {e}", dir.display())))?;
        if !root.join(WASM_FILE).is_file() {
            return Err(SimError::Usage(format!(
                "{}: missing; build it first with `{BUILD_HINT}` (it compiles the kernel to WebAssembly)",
                root.join(WASM_FILE).display()
            )));
        }
        Ok(Site::Folder(root))
    }
}

/// Runs `picomis-sim serve` until the process is stopped.
pub fn run(args: &ServeArgs) -> Result<(), SimError> {
    let site = Site::of(args.dir.as_deref())?;
    let addr = SocketAddr::new(args.bind, args.port);
    let listener = TcpListener::bind(addr).map_err(|e| SimError::Io(format!("{addr}: {e}")))?;
    let local = listener.local_addr().map_err(|e| SimError::Io(e.to_string()))?;
    let host = match local.ip() {
        IpAddr::V6(ip) => format!("[{ip}]"),
        IpAddr::V4(ip) => ip.to_string(),
    };
    let what = match &site {
        Site::BuiltIn => "the page built into picomis-sim".to_string(),
        Site::Folder(root) => root.display().to_string(),
    };
    println!("serving {what} at http://{host}:{}/ (Ctrl-C to stop)", local.port());
    std::io::stdout().flush().map_err(|e| SimError::Io(e.to_string()))?;
    serve(listener, site);
    Ok(())
}

/// Serves `site` on `listener` forever, one thread per connection.
pub fn serve(listener: TcpListener, site: Site) {
    let site = Arc::new(site);
    let active = Arc::new(AtomicUsize::new(0));
    for stream in listener.incoming() {
        let Ok(stream) = stream else { continue };
        if active.fetch_add(1, Ordering::SeqCst) >= MAX_CONNECTIONS {
            active.fetch_sub(1, Ordering::SeqCst);
            continue; // dropped: closes the connection
        }
        let (site, active) = (Arc::clone(&site), Arc::clone(&active));
        std::thread::spawn(move || {
            let _ = handle(stream, &site);
            active.fetch_sub(1, Ordering::SeqCst);
        });
    }
}

/// Why a request gets no file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Reject {
    /// 400: not a path of this server (malformed, bad escapes, absolute-form).
    BadRequest,
    /// 403: a path that tries to leave the folder or go through a link.
    Forbidden,
    /// 404: no such page file (missing, a directory, hidden, or not a page file type).
    NotFound,
}

impl Reject {
    fn status(self) -> (u16, &'static str) {
        match self {
            Reject::BadRequest => (400, "Bad Request"),
            Reject::Forbidden => (403, "Forbidden"),
            Reject::NotFound => (404, "Not Found"),
        }
    }
}

/// The content type of a page file, by extension; `None` for anything else (not served).
pub fn content_type(path: &Path) -> Option<&'static str> {
    let ext = path.extension()?.to_str()?;
    Some(match ext {
        "html" => "text/html; charset=utf-8",
        "js" | "mjs" => "text/javascript; charset=utf-8",
        "css" => "text/css; charset=utf-8",
        "wasm" => "application/wasm",
        "json" => "application/json",
        "png" => "image/png",
        "svg" => "image/svg+xml",
        "ico" => "image/x-icon",
        "txt" => "text/plain; charset=utf-8",
        _ => return None,
    })
}

fn hex(b: u8) -> Option<u8> {
    char::from(b).to_digit(16).map(|d| d as u8)
}

/// The name a request target asks for: the target's path (query and fragment dropped),
/// percent-decoded once, `index.html` for `/`. After decoding it must be a `/`-separated list
/// of plain names: no empty, `.` or `..` segments, no backslash, colon or NUL (forbidden), and
/// no hidden (`.`-prefixed) names (not found).
pub fn request_path(target: &str) -> Result<String, Reject> {
    let path = target.split(['?', '#']).next().unwrap_or("");
    let Some(path) = path.strip_prefix('/') else { return Err(Reject::BadRequest) };
    let mut bytes = Vec::with_capacity(path.len());
    let mut raw = path.bytes();
    while let Some(b) = raw.next() {
        if b == b'%' {
            let (Some(h), Some(l)) = (raw.next().and_then(hex), raw.next().and_then(hex)) else {
                return Err(Reject::BadRequest);
            };
            bytes.push(h << 4 | l);
        } else {
            bytes.push(b);
        }
    }
    let decoded = String::from_utf8(bytes).map_err(|_| Reject::BadRequest)?;
    let decoded = if decoded.is_empty() { "index.html".to_string() } else { decoded };
    if decoded.contains(['\\', '\0', ':']) {
        return Err(Reject::Forbidden);
    }
    let segments = decoded.split('/');
    if segments.clone().any(|s| s == ".." || s == "." || s.is_empty()) {
        return Err(Reject::Forbidden);
    }
    if segments.clone().any(|s| s.starts_with('.')) {
        return Err(Reject::NotFound);
    }
    Ok(decoded)
}

/// The file of the built-in page ([`crate::page`]) that request target `target` asks for
/// ([`request_path`]), and its content type.
pub fn built_in(target: &str) -> Result<(&'static [u8], &'static str), Reject> {
    let name = request_path(target)?;
    let body = page::file(&name).ok_or(Reject::NotFound)?;
    Ok((body, content_type(Path::new(&name)).ok_or(Reject::NotFound)?))
}

/// The file under `root` (canonical) that request target `target` asks for
/// ([`request_path`]), and its content type. Every existing prefix is checked not to be a
/// symlink, the file must be a regular file with a page type ([`content_type`]), and its
/// canonical path must lie in `root`.
pub fn resolve(root: &Path, target: &str) -> Result<(PathBuf, &'static str), Reject> {
    let name = request_path(target)?;
    let mut file = root.to_path_buf();
    for segment in name.split('/') {
        file.push(segment);
        match std::fs::symlink_metadata(&file) {
            Ok(m) if m.file_type().is_symlink() => return Err(Reject::Forbidden),
            Ok(_) => {}
            Err(_) => return Err(Reject::NotFound),
        }
    }
    let content_type = content_type(&file).ok_or(Reject::NotFound)?;
    let meta = std::fs::metadata(&file).map_err(|_| Reject::NotFound)?;
    if !meta.is_file() {
        return Err(Reject::NotFound); // no directory listing
    }
    let canonical = file.canonicalize().map_err(|_| Reject::NotFound)?;
    if !canonical.starts_with(root) {
        return Err(Reject::Forbidden);
    }
    Ok((canonical, content_type))
}

/// The body and content type `site` answers `target` with.
fn lookup(site: &Site, target: &str) -> Result<(Cow<'static, [u8]>, &'static str), Reject> {
    match site {
        Site::BuiltIn => built_in(target).map(|(body, ct)| (Cow::Borrowed(body), ct)),
        Site::Folder(root) => {
            let (path, ct) = resolve(root, target)?;
            let meta = std::fs::metadata(&path).map_err(|_| Reject::NotFound)?;
            if meta.len() > MAX_FILE {
                return Err(Reject::NotFound);
            }
            std::fs::read(&path).map(|body| (Cow::Owned(body), ct)).map_err(|_| Reject::NotFound)
        }
    }
}

/// Reads the request head: at most [`MAX_REQUEST`] bytes, up to the empty line.
fn read_head(stream: &TcpStream) -> Result<Vec<String>, Reject> {
    let mut reader = BufReader::new(stream.take(MAX_REQUEST as u64));
    let mut lines = Vec::new();
    loop {
        let mut line = Vec::new();
        let n = reader.read_until(b'\n', &mut line).map_err(|_| Reject::BadRequest)?;
        if n == 0 || !line.ends_with(b"\n") {
            return Err(Reject::BadRequest); // closed early or too long
        }
        let line = String::from_utf8(line).map_err(|_| Reject::BadRequest)?;
        let line = line.trim_end_matches(['\r', '\n']);
        if line.is_empty() {
            return Ok(lines);
        }
        lines.push(line.to_string());
    }
}

fn respond(stream: &mut TcpStream, status: (u16, &str), content_type: &str, body: &[u8], head_only: bool) {
    let head = format!(
        "HTTP/1.1 {} {}\r\nContent-Type: {content_type}\r\nContent-Length: {}\r\n\
         X-Content-Type-Options: nosniff\r\nCache-Control: no-cache\r\nConnection: close\r\n\r\n",
        status.0,
        status.1,
        body.len()
    );
    let _ = stream.write_all(head.as_bytes());
    if !head_only {
        let _ = stream.write_all(body);
    }
    let _ = stream.flush();
}

fn handle(mut stream: TcpStream, site: &Site) -> std::io::Result<()> {
    stream.set_read_timeout(Some(TIMEOUT))?;
    stream.set_write_timeout(Some(TIMEOUT))?;
    respond_to(&mut stream, site);
    // Lingering close: read (a bounded amount of) what the client still sends, so that closing
    // with unread data does not reset the connection before the client has read the response.
    stream.shutdown(std::net::Shutdown::Write)?;
    stream.set_read_timeout(Some(Duration::from_secs(1)))?;
    let _ = std::io::copy(&mut (&stream).take(1 << 20), &mut std::io::sink());
    Ok(())
}

fn respond_to(stream: &mut TcpStream, site: &Site) {
    let error = |stream: &mut TcpStream, r: Reject, head_only: bool| {
        let status = r.status();
        let body = format!("{} {}\n", status.0, status.1);
        respond(stream, status, "text/plain; charset=utf-8", body.as_bytes(), head_only);
    };
    let lines = match read_head(stream) {
        Ok(lines) => lines,
        Err(r) => {
            error(stream, r, false);
            return;
        }
    };
    let request_line = lines.first().map(String::as_str).unwrap_or("");
    let parts: Vec<&str> = request_line.split(' ').collect();
    let [method, target, version] = parts[..] else {
        error(stream, Reject::BadRequest, false);
        return;
    };
    if !version.starts_with("HTTP/1.") {
        error(stream, Reject::BadRequest, false);
        return;
    }
    let head_only = match method {
        "GET" => false,
        "HEAD" => true,
        _ => {
            let body = b"405 Method Not Allowed\n";
            respond(stream, (405, "Method Not Allowed"), "text/plain; charset=utf-8", body, false);
            return;
        }
    };
    match lookup(site, target) {
        Ok((body, ct)) => respond(stream, (200, "OK"), ct, &body, head_only),
        Err(r) => error(stream, r, head_only),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn site() -> (tempfile::TempDir, PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let root = dir.path().join("site");
        std::fs::create_dir_all(root.join("sub")).unwrap();
        std::fs::write(root.join("index.html"), "<p>hi</p>").unwrap();
        std::fs::write(root.join("sub/a.js"), "1").unwrap();
        std::fs::write(root.join("x.wasm"), "\0asm").unwrap();
        std::fs::write(root.join("notes.rs"), "fn main() {}").unwrap();
        std::fs::write(root.join(".hidden.txt"), "no").unwrap();
        std::fs::write(dir.path().join("secret.txt"), "secret").unwrap();
        #[cfg(unix)]
        {
            std::os::unix::fs::symlink(dir.path().join("secret.txt"), root.join("link.txt")).unwrap();
            std::os::unix::fs::symlink(dir.path(), root.join("up")).unwrap();
        }
        let root = root.canonicalize().unwrap();
        (dir, root)
    }

    #[test]
    fn serves_page_files_with_their_types() {
        let (_dir, root) = site();
        assert_eq!(resolve(&root, "/").unwrap(), (root.join("index.html"), "text/html; charset=utf-8"));
        assert_eq!(resolve(&root, "/index.html?x=1#y").unwrap().0, root.join("index.html"));
        assert_eq!(resolve(&root, "/x.wasm").unwrap().1, "application/wasm");
        assert_eq!(resolve(&root, "/sub/a.js").unwrap().1, "text/javascript; charset=utf-8");
        assert_eq!(resolve(&root, "/sub%2Fa.js").unwrap().0, root.join("sub/a.js"));
        assert_eq!(resolve(&root, "/%69ndex.html").unwrap().0, root.join("index.html"));
    }

    #[test]
    fn never_leaves_the_folder() {
        let (_dir, root) = site();
        let cases = [
            ("/../secret.txt", Reject::Forbidden),
            ("/sub/../../secret.txt", Reject::Forbidden),
            ("/%2e%2e/secret.txt", Reject::Forbidden),
            ("/%2E%2E%2Fsecret.txt", Reject::Forbidden),
            ("/..%2fsecret.txt", Reject::Forbidden),
            ("/sub/%2e%2e%2f%2e%2e%2fsecret.txt", Reject::Forbidden),
            ("/%252e%252e/secret.txt", Reject::NotFound), // decoded once: a name "%2e%2e"
            ("/..\\secret.txt", Reject::Forbidden),
            ("/%5c..%5csecret.txt", Reject::Forbidden),
            ("//etc/passwd", Reject::Forbidden),
            ("/%2fetc/passwd", Reject::Forbidden),
            ("/etc/passwd", Reject::NotFound),
            ("/C:/x.txt", Reject::Forbidden),
            ("/index.html%00.png", Reject::Forbidden),
            ("/./index.html", Reject::Forbidden),
            ("http://localhost/index.html", Reject::BadRequest),
            ("*", Reject::BadRequest),
            ("/%zz", Reject::BadRequest),
            ("/%e2%28", Reject::BadRequest),
            ("/link.txt", Reject::Forbidden),
            ("/up/secret.txt", Reject::Forbidden),
            ("/sub", Reject::NotFound),
            ("/sub/", Reject::Forbidden),
            ("/notes.rs", Reject::NotFound),
            ("/.hidden.txt", Reject::NotFound),
            ("/missing.html", Reject::NotFound),
        ];
        for (target, expected) in cases {
            assert_eq!(resolve(&root, target).map(|(p, _)| p), Err(expected), "{target}");
        }
        let absolute = format!("/{}", root.join("index.html").display());
        assert!(resolve(&root, &absolute).is_err(), "{absolute}");
    }

    #[test]
    fn the_built_in_page_answers_its_own_names_only() {
        let (index, ct) = built_in("/").unwrap();
        assert_eq!((index, ct), (page::FILES[0].1, "text/html; charset=utf-8"));
        assert_eq!(built_in("/worker.js?x=1").unwrap().1, "text/javascript; charset=utf-8");
        assert_eq!(built_in("/%77orker.js").unwrap().1, "text/javascript; charset=utf-8");
        match page::wasm() {
            Ok(wasm) => assert_eq!(built_in("/picomis.wasm").unwrap(), (wasm, "application/wasm")),
            Err(_) => assert_eq!(built_in("/picomis.wasm"), Err(Reject::NotFound)),
        }
        let cases = [
            ("/../index.html", Reject::Forbidden),
            ("/%2e%2e/index.html", Reject::Forbidden),
            ("/sub/../index.html", Reject::Forbidden),
            ("/..\\index.html", Reject::Forbidden),
            ("//index.html", Reject::Forbidden),
            ("/./index.html", Reject::Forbidden),
            ("/index.html%00", Reject::Forbidden),
            ("/.index.html", Reject::NotFound),
            ("/sub/index.html", Reject::NotFound),
            ("/Cargo.toml", Reject::NotFound),
            ("/wasm/src/lib.rs", Reject::NotFound),
            ("/index.htm", Reject::NotFound),
            ("http://localhost/index.html", Reject::BadRequest),
            ("/%zz", Reject::BadRequest),
        ];
        for (target, expected) in cases {
            assert_eq!(built_in(target).map(|(b, _)| b.len()), Err(expected), "{target}");
        }
    }
}
