//! Rows: functions that cannot fail, each with a check of how it takes its own odd inputs.

use crate::{set_sentinel_error, table::Table, values::last_error};
use crowdgaze::ffi::crowd::*;
use crowdgaze::ffi::last_error::cg_last_error_message;
use crowdgaze::ffi::status::{cg_status, cg_status_str};
use crowdgaze::ffi::version::*;
use crowdgaze::ffi::view_blender::*;
use std::collections::BTreeSet;
use std::ffi::{c_char, CStr};
use std::ptr::null_mut;

pub(crate) fn rows_infallible(t: &mut Table) {
    t.no_failure_modes(
        "cg_crowd_destroy",
        "returns nothing; NULL is accepted and ignored",
        || {
            let before = set_sentinel_error();
            unsafe { cg_crowd_destroy(null_mut()) };
            assert_eq!(
                last_error(),
                before,
                "cg_crowd_destroy(NULL) recorded an error"
            );
        },
    );
    t.no_failure_modes(
        "cg_view_blender_destroy",
        "returns nothing; NULL is accepted and ignored",
        || {
            let before = set_sentinel_error();
            unsafe { cg_view_blender_destroy(null_mut()) };
            assert_eq!(last_error(), before);
        },
    );
    t.no_failure_modes(
        "cg_last_error_message",
        "returns a length; a NULL or short buffer is documented",
        check_last_error_message,
    );
    t.no_failure_modes(
        "cg_status_str",
        "an unknown status gives \"unknown status\", never NULL",
        || {
            let first_unknown = cg_status::ALL.len() as u32;
            for value in [first_unknown, first_unknown + 1, 255, 0x8000_0000, u32::MAX] {
                let text = cg_status_str(value);
                assert!(!text.is_null(), "cg_status_str({value}) is NULL");
                // SAFETY: non-NULL, static and NUL-terminated by contract.
                let text = unsafe { CStr::from_ptr(text) };
                assert_eq!(
                    text.to_str(),
                    Ok("unknown status"),
                    "cg_status_str({value})"
                );
            }
            let known: BTreeSet<_> = cg_status::ALL
                .iter()
                // SAFETY: as above.
                .map(|s| unsafe { CStr::from_ptr(cg_status_str(*s as u32)) })
                .collect();
            assert_eq!(
                known.len(),
                cg_status::ALL.len(),
                "descriptions are distinct"
            );
            assert!(!known.contains(c"unknown status"));
        },
    );
    t.no_failure_modes("cg_version", "takes nothing; a constant", || {
        assert_eq!(
            cg_version(),
            (CG_VERSION_MAJOR << 16) | (CG_VERSION_MINOR << 8) | CG_VERSION_PATCH
        );
    });
    t.no_failure_modes(
        "cg_version_string",
        "takes nothing; a static string",
        || {
            // SAFETY: static and NUL-terminated by contract.
            let text = unsafe { CStr::from_ptr(cg_version_string()) };
            let expected = format!("{CG_VERSION_MAJOR}.{CG_VERSION_MINOR}.{CG_VERSION_PATCH}");
            assert_eq!(text.to_str(), Ok(expected.as_str()));
        },
    );
}

/// `cg_last_error_message` with a NULL buffer, a zero length, a one-byte buffer and a short
/// one: the full length always comes back, at most `len - 1` bytes and a NUL are written.
fn check_last_error_message() {
    let message = set_sentinel_error();
    let length = message.len();
    assert!(length > 8);
    assert_eq!(unsafe { cg_last_error_message(null_mut(), 0) }, length);
    assert_eq!(unsafe { cg_last_error_message(null_mut(), 100) }, length);
    let mut buf = [0x5Au8; 64];
    let pointer = buf.as_mut_ptr().cast::<c_char>();
    assert_eq!(unsafe { cg_last_error_message(pointer, 0) }, length);
    assert!(buf.iter().all(|&b| b == 0x5A), "len 0 wrote");
    assert_eq!(unsafe { cg_last_error_message(pointer, 1) }, length);
    assert_eq!(buf[0], 0, "len 1 writes the NUL alone");
    assert!(buf[1..].iter().all(|&b| b == 0x5A));
    assert_eq!(unsafe { cg_last_error_message(pointer, 6) }, length);
    assert_eq!(
        &buf[..6],
        &[message.as_bytes()[..5].to_vec(), vec![0]].concat()[..]
    );
    assert!(buf[6..].iter().all(|&b| b == 0x5A), "wrote past len");
    // A message is kept until the next failure on this thread, and is per thread.
    assert_eq!(
        std::thread::spawn(|| unsafe { cg_last_error_message(null_mut(), 0) })
            .join()
            .expect("thread"),
        0
    );
    assert_eq!(last_error(), message);
}
