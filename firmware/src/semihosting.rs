//! The few semihosting calls the firmware needs under QEMU: write a host file or the host's
//! stdout, exit with a code. The trap itself is per architecture (`arch::semihosting_call`).

use crate::arch::semihosting_call;

const SYS_OPEN: usize = 0x01;
const SYS_CLOSE: usize = 0x02;
const SYS_WRITE: usize = 0x05;
/// SYS_EXIT_EXTENDED: exit with any status code (SYS_EXIT only tells success or failure).
const SYS_EXIT_EXTENDED: usize = 0x20;
/// ADP_Stopped_ApplicationExit.
const APPLICATION_EXIT: usize = 0x20026;
/// SYS_OPEN modes: "w" (text, for the log) and "wb".
#[cfg(not(feature = "rtt"))]
const MODE_W: usize = 4;
const MODE_WB: usize = 5;

/// Why a host file could not be written.
#[derive(Clone, Copy, Debug)]
pub enum FileError {
    /// The path is not NUL-terminated.
    Path,
    /// SYS_OPEN failed.
    Open,
    /// SYS_WRITE wrote nothing.
    Write,
    /// SYS_CLOSE failed.
    Close,
}

/// Opens the host file `path` (NUL-terminated) with `mode`; returns the handle.
fn open(path: &[u8], mode: usize) -> Result<usize, FileError> {
    let Some((&0, name)) = path.split_last() else { return Err(FileError::Path) };
    let block = [path.as_ptr() as usize, mode, name.len()];
    let fd = semihosting_call(SYS_OPEN, block.as_ptr() as usize) as isize;
    if fd < 0 { Err(FileError::Open) } else { Ok(fd as usize) }
}

/// Writes all of `data` to the host handle `fd`.
pub fn write(fd: usize, data: &[u8]) -> Result<(), FileError> {
    let mut rest = data;
    while !rest.is_empty() {
        let block = [fd, rest.as_ptr() as usize, rest.len()];
        // WRITE returns the count NOT written.
        let left = semihosting_call(SYS_WRITE, block.as_ptr() as usize);
        if left >= rest.len() {
            return Err(FileError::Write);
        }
        rest = &rest[rest.len() - left..];
    }
    Ok(())
}

/// A handle on the host's stdout (the special file `:tt`), for the text log.
#[cfg(not(feature = "rtt"))]
pub fn stdout() -> Result<usize, FileError> {
    open(b":tt\0", MODE_W)
}

/// Writes `data` to the host file `path` (NUL-terminated; relative to QEMU's working directory).
pub fn write_file(path: &[u8], data: &[u8]) -> Result<(), FileError> {
    let fd = open(path, MODE_WB)?;
    let result = write(fd, data);
    let block = [fd];
    let closed = semihosting_call(SYS_CLOSE, block.as_ptr() as usize);
    if closed != 0 && result.is_ok() {
        return Err(FileError::Close);
    }
    result
}

/// Ends the QEMU run with `code` as its exit status.
pub fn exit(code: u32) -> ! {
    let block = [APPLICATION_EXIT, code as usize];
    loop {
        semihosting_call(SYS_EXIT_EXTENDED, block.as_ptr() as usize);
    }
}
