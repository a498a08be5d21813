//! Plain-text logging over semihosting without `core::fmt` (which would cost kilobytes of
//! flash): `info!("a {} b {}", x, s)` splits the literal at each `{}` and writes the arguments
//! (integers and strings) in order, one SYS_WRITE per line.

use core::sync::atomic::{AtomicUsize, Ordering};

use crate::semihosting;

/// The host's stdout handle plus one, opened on first use (0: not open yet).
static STDOUT: AtomicUsize = AtomicUsize::new(0);

/// A value `info!` can print.
pub trait Arg {
    /// Appends the value to `line`.
    fn put(&self, line: &mut Line);
}

/// A line being assembled (long lines are cut).
pub struct Line {
    buf: [u8; 160],
    len: usize,
}

impl Line {
    fn push(&mut self, bytes: &[u8]) {
        let n = bytes.len().min(self.buf.len() - self.len);
        self.buf[self.len..self.len + n].copy_from_slice(&bytes[..n]);
        self.len += n;
    }

    fn decimal(&mut self, mut v: u64) {
        let mut digits = [0u8; 20];
        let mut i = digits.len();
        loop {
            i -= 1;
            // u32 arithmetic where possible: u64 division is a library call on Cortex-M.
            let d = if v <= u64::from(u32::MAX) {
                let w = v as u32;
                v = u64::from(w / 10);
                (w % 10) as u8
            } else {
                let q = v / 10;
                let d = (v - q * 10) as u8;
                v = q;
                d
            };
            digits[i] = b'0' + d;
            if v == 0 {
                break;
            }
        }
        self.push(&digits[i..]);
    }
}

impl Arg for u32 {
    fn put(&self, line: &mut Line) {
        line.decimal(u64::from(*self));
    }
}

impl Arg for u64 {
    fn put(&self, line: &mut Line) {
        line.decimal(*self);
    }
}

impl Arg for usize {
    fn put(&self, line: &mut Line) {
        line.decimal(*self as u64);
    }
}

impl Arg for &str {
    fn put(&self, line: &mut Line) {
        line.push(self.as_bytes());
    }
}

/// Writes `fmt` with each `{}` replaced by the next argument, and a newline.
pub fn print(fmt: &str, args: &[&dyn Arg]) {
    let mut line = Line { buf: [0; 160], len: 0 };
    let mut args = args.iter();
    // Bytes, not str slicing: str boundary checks would link core::fmt and Unicode tables.
    let mut rest = fmt.as_bytes();
    while let Some(at) = rest.windows(2).position(|w| w == b"{}") {
        let (text, tail) = rest.split_at(at);
        line.push(text);
        if let Some(a) = args.next() {
            a.put(&mut line);
        }
        rest = tail.get(2..).unwrap_or(&[]);
    }
    line.push(rest);
    line.push(b"\n");
    // Only `main` logs (no exception handler does), so a plain load and store suffice.
    let fd = match STDOUT.load(Ordering::Relaxed) {
        0 => semihosting::stdout().ok().inspect(|&fd| STDOUT.store(fd + 1, Ordering::Relaxed)),
        h => Some(h - 1),
    };
    if let Some(fd) = fd {
        let _ = semihosting::write(fd, &line.buf[..line.len]);
    }
}
