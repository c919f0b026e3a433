//! The calling thread's last error message, and `cg_last_error_message` to read it from C.

use libc::c_char;
use std::cell::RefCell;

use super::error::FfiError;
use super::status::cg_status;

thread_local! {
    static LAST_ERROR: RefCell<String> = const { RefCell::new(String::new()) };
}

/// Records `error` as this thread's last error and returns its status.
pub(crate) fn record(error: &FfiError) -> cg_status {
    LAST_ERROR.with(|slot| {
        let mut message = slot.borrow_mut();
        message.clear();
        use std::fmt::Write;
        let _ = write!(message, "{error}");
    });
    cg_status::from(error)
}

/// This thread's last error message (empty if no call has failed on this thread yet).
pub fn last_error_message() -> String {
    LAST_ERROR.with(|slot| slot.borrow().clone())
}

/// Copies the calling thread's last error message into `buf` and returns its full length
/// in bytes (not counting the terminating NUL).
///
/// The message is one line of English describing the most recent failed crowdgaze call on
/// *this thread*; successful calls do not clear it. It is empty (length 0) if no call has
/// failed on this thread yet.
///
/// `buf` may be NULL or `len` 0: nothing is written and the length is still returned, so a
/// caller can size a buffer. Otherwise at most `len - 1` bytes are copied, always followed
/// by a NUL; a return value `>= len` means the message was truncated. The caller owns
/// `buf`. Thread-safe (each thread has its own message).
#[no_mangle]
pub unsafe extern "C" fn cg_last_error_message(
    buf: *mut c_char,
    len: libc::size_t,
) -> libc::size_t {
    let copy = std::panic::catch_unwind(|| {
        LAST_ERROR.with(|slot| {
            // SAFETY: the caller's buffer of `len` writable bytes (or NULL).
            unsafe { copy_text(&slot.borrow(), buf, len) }
        })
    });
    copy.unwrap_or(0)
}

/// Copies `text` into the caller's `buf` of `len` bytes, truncated to `len - 1` bytes and
/// NUL-terminated (nothing if `buf` is NULL or `len` 0), and returns its full length.
///
/// # Safety
/// `buf`, if not NULL, must point to at least `len` writable bytes.
pub(crate) unsafe fn copy_text(text: &str, buf: *mut c_char, len: usize) -> usize {
    let bytes = text.as_bytes();
    if !buf.is_null() && len > 0 {
        let count = bytes.len().min(len - 1);
        // SAFETY: the caller promises `buf` points to at least `len` writable bytes; we
        // write `count + 1 <= len` of them.
        unsafe {
            core::ptr::copy_nonoverlapping(bytes.as_ptr(), buf.cast::<u8>(), count);
            *buf.add(count) = 0;
        }
    }
    bytes.len()
}
