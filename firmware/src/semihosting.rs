//! The few semihosting calls the firmware needs under QEMU: write a host file, exit with a code.

use cortex_m_semihosting::{nr, syscall, syscall1};

/// SYS_EXIT_EXTENDED: exit with any status code (SYS_EXIT only tells success or failure).
const SYS_EXIT_EXTENDED: usize = 0x20;
/// ADP_Stopped_ApplicationExit.
const APPLICATION_EXIT: usize = 0x20026;

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

/// Writes `data` to the host file `path` (NUL-terminated; relative to QEMU's working directory).
pub fn write_file(path: &[u8], data: &[u8]) -> Result<(), FileError> {
    let Some((&0, name)) = path.split_last() else { return Err(FileError::Path) };
    // SAFETY: OPEN reads `name.len()` bytes of a NUL-terminated string that outlives the call.
    let fd = unsafe { syscall!(OPEN, path.as_ptr(), nr::open::W_TRUNC_BINARY, name.len()) } as isize;
    if fd < 0 {
        return Err(FileError::Open);
    }
    let mut rest = data;
    let mut result = Ok(());
    while !rest.is_empty() {
        // SAFETY: WRITE reads `rest.len()` bytes from `rest`; it returns the count NOT written.
        let left = unsafe { syscall!(WRITE, fd, rest.as_ptr(), rest.len()) };
        if left >= rest.len() {
            result = Err(FileError::Write);
            break;
        }
        rest = &rest[rest.len() - left..];
    }
    // SAFETY: closes the handle opened above.
    let closed = unsafe { syscall!(CLOSE, fd) };
    if closed != 0 && result.is_ok() {
        result = Err(FileError::Close);
    }
    result
}

/// Ends the QEMU run with `code` as its exit status.
pub fn exit(code: u32) -> ! {
    let block = [APPLICATION_EXIT, code as usize];
    loop {
        // SAFETY: SYS_EXIT_EXTENDED reads the two-word block, which lives across the call.
        unsafe { syscall1(SYS_EXIT_EXTENDED, block.as_ptr() as usize) };
    }
}
