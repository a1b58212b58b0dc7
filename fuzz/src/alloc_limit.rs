//! The fuzz binaries' global allocator: the system allocator, except that one allocation over
//! [`LIMIT`] aborts the process with a message, which libFuzzer records as a failing input.
//! This is the "no allocation over 2 GiB" check without AddressSanitizer's malloc hooks (the
//! binaries run without ASan: on the DSL compiler it cost 16× the executions per second).

use std::alloc::{GlobalAlloc, Layout, System};

/// The largest single allocation an input may make.
pub const LIMIT: usize = 2 << 30;

/// [`System`], refusing allocations over [`LIMIT`].
#[derive(Debug)]
pub struct LimitedAllocator;

impl LimitedAllocator {
    fn check(size: usize) {
        if size > LIMIT {
            let message = b"fuzz: an allocation over 2 GiB\n";
            // SAFETY: writing a static buffer to stderr, then aborting; no allocation here.
            unsafe {
                libc_write(2, message.as_ptr(), message.len());
            }
            std::process::abort();
        }
    }
}

unsafe extern "C" {
    #[link_name = "write"]
    fn libc_write(fd: i32, buf: *const u8, count: usize) -> isize;
}

// SAFETY: every call forwards to `System` with the caller's layout and pointer, unchanged.
unsafe impl GlobalAlloc for LimitedAllocator {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        Self::check(layout.size());
        // SAFETY: the caller's contract is `System::alloc`'s.
        unsafe { System.alloc(layout) }
    }

    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        Self::check(layout.size());
        // SAFETY: as for `alloc`.
        unsafe { System.alloc_zeroed(layout) }
    }

    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        // SAFETY: `ptr` came from this allocator, that is from `System`, with `layout`.
        unsafe { System.dealloc(ptr, layout) }
    }

    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        Self::check(new_size);
        // SAFETY: as for `dealloc`; `new_size` is the caller's.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}
