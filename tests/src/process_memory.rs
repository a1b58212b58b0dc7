//! What a long run accumulates, as the robustness tests measure it: the wgpu objects the
//! application holds (wgpu-core's report), the bytes glibc's allocator has handed out and not
//! had back, what the Rust side of it allocated (a counting allocator), and the process's
//! resident memory. Plus a frame's lit-pixel statistics, so a test
//! comparing two frames can first show that neither is black.

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::atomic::{AtomicI64, Ordering::Relaxed};

use renderer::GpuContext;

/// wgpu objects the application holds: buffers, textures, texture views, bind groups, render
/// pipelines, compute pipelines and query sets, from the instance's report.
pub fn live_objects(gpu: &GpuContext) -> [usize; 7] {
    let report = gpu.instance().generate_report().expect("wgpu-core report");
    let h = report.hub_report();
    [
        &h.buffers,
        &h.textures,
        &h.texture_views,
        &h.bind_groups,
        &h.render_pipelines,
        &h.compute_pipelines,
        &h.query_sets,
    ]
    .map(|r| r.num_kept_from_user)
}

/// glibc's `mallinfo2`: the heap's statistics.
#[repr(C)]
#[derive(Debug, Default)]
struct MallInfo2 {
    arena: usize,
    ordblks: usize,
    smblks: usize,
    hblks: usize,
    hblkhd: usize,
    usmblks: usize,
    fsmblks: usize,
    uordblks: usize,
    fordblks: usize,
    keepcost: usize,
}

unsafe extern "C" {
    fn mallinfo2() -> MallInfo2;
    fn malloc_trim(pad: usize) -> i32;
}

/// Bytes the process has allocated and not freed (glibc's heap and mmap'd blocks): what a leak
/// grows, unlike resident memory, which also keeps freed pages the allocator has not returned.
/// Lavapipe allocates its device memory with the same allocator, so leaked GPU memory counts.
pub fn heap_in_use() -> u64 {
    // SAFETY: a read-only query of glibc's allocator statistics.
    let info = unsafe { mallinfo2() };
    (info.uordblks + info.hblkhd) as u64
}

/// Resident memory of this process, bytes (Linux `/proc/self/statm`).
///
/// The allocator first gives back the free pages of every arena (glibc's `malloc_trim`), so
/// memory it keeps free, which depends on which thread's arena blocks landed in, does not
/// count as growth: a busy CI machine once saw resident memory grow by 54 MiB between two
/// checkpoints while the heap in use stayed within 5 KiB.
pub fn resident_bytes() -> u64 {
    // SAFETY: asks glibc's allocator to return free memory to the system; no block moves.
    unsafe { malloc_trim(0) };
    let statm = std::fs::read_to_string("/proc/self/statm").expect("/proc/self/statm");
    let pages: u64 = statm
        .split_whitespace()
        .nth(1)
        .and_then(|p| p.parse().ok())
        .expect("resident pages");
    pages * 4096
}

/// How lit an RGBA8 frame is: the mean Rec. 709 luma of its stored values (0–255) and how many
/// pixels have a luma of at least `floor`.
pub fn lit_pixels(rgba: &[u8], floor: f32) -> (f32, usize) {
    let luma =
        |p: &[u8]| 0.2126 * f32::from(p[0]) + 0.7152 * f32::from(p[1]) + 0.0722 * f32::from(p[2]);
    let pixels = rgba.len() / 4;
    let sum: f32 = rgba.chunks_exact(4).map(luma).sum();
    let lit = rgba.chunks_exact(4).filter(|p| luma(p) >= floor).count();
    (sum / pixels.max(1) as f32, lit)
}

/// Bytes the Rust side of the process (renderer, wgpu, tests) has allocated and not freed.
pub static RUST_HEAP: AtomicI64 = AtomicI64::new(0);

/// The system allocator, counting into [`RUST_HEAP`]: a test binary that wants the figure
/// declares `#[global_allocator] static A: Counting = Counting;`.
#[derive(Debug)]
pub struct Counting;

// SAFETY: every call forwards to the system allocator with the caller's arguments.
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        RUST_HEAP.fetch_add(layout.size() as i64, Relaxed);
        // SAFETY: the caller's layout, as `GlobalAlloc::alloc` requires.
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        RUST_HEAP.fetch_sub(layout.size() as i64, Relaxed);
        // SAFETY: a pointer this allocator returned, with its layout.
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        RUST_HEAP.fetch_add(new_size as i64 - layout.size() as i64, Relaxed);
        // SAFETY: a pointer this allocator returned, with its layout.
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

/// Timestamp query pools wgpu-profiler may hold: it keeps its pools for reuse and adds one when
/// a frame needs more queries than they hold (measured 2 to 3 over the soak, the third arriving
/// at a different frame from run to run, as frames in flight vary).
pub const MAX_PROFILER_POOLS: usize = 6;

/// What a long run's checkpoint measured: bytes (glibc's heap in use, the Rust side's heap,
/// resident memory), the live objects of [`live_objects`] and the transient pool's entries.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Checkpoint {
    pub frame: usize,
    pub heap: i64,
    pub rust_heap: i64,
    pub resident: i64,
    pub objects: [usize; 7],
    pub pool_held: usize,
}

impl Checkpoint {
    /// The figures now, after frame `frame` whose pool held `pool_held` entries (the Rust heap
    /// reads 0 unless the binary counts with [`Counting`]).
    pub fn take(gpu: &GpuContext, frame: usize, pool_held: usize) -> Self {
        Self {
            frame,
            heap: heap_in_use() as i64,
            rust_heap: RUST_HEAP.load(Relaxed),
            resident: resident_bytes() as i64,
            objects: live_objects(gpu),
            pool_held,
        }
    }

    /// The objects without wgpu-profiler's timestamp query pools (each a query set and two
    /// buffers, kept for reuse and added when a frame needs more queries than the pools hold),
    /// and the number of those pools.
    fn objects_without_profiler_pools(&self) -> ([usize; 7], usize) {
        let pools = self.objects[6];
        let mut objects = self.objects;
        objects[0] = objects[0].saturating_sub(2 * pools);
        objects[6] = 0;
        (objects, pools)
    }

    /// Panics unless `self` holds exactly `settled`'s objects and pool entries (apart from at
    /// most [`MAX_PROFILER_POOLS`] timestamp query pools), and its heap, Rust heap and resident
    /// memory grew from `settled`'s by at most `limits` bytes.
    pub fn assert_within(&self, settled: &Checkpoint, limits: [i64; 3]) {
        let (now, then) = (self.frame, settled.frame);
        let (objects, pools) = self.objects_without_profiler_pools();
        assert_eq!(
            (objects, self.pool_held),
            (
                settled.objects_without_profiler_pools().0,
                settled.pool_held
            ),
            "live wgpu objects (without timestamp query pools) and pool entries at frame {now} \
             against frame {then}"
        );
        assert!(
            pools <= MAX_PROFILER_POOLS,
            "{pools} timestamp query pools at frame {now} (at most {MAX_PROFILER_POOLS})"
        );
        let grown = [
            ("heap in use", self.heap - settled.heap),
            ("Rust heap", self.rust_heap - settled.rust_heap),
            ("resident memory", self.resident - settled.resident),
        ];
        for ((what, growth), limit) in grown.into_iter().zip(limits) {
            assert!(
                growth <= limit,
                "the {what} grew by {} KiB from frame {then} to frame {now} (limit {} KiB)",
                growth >> 10,
                limit >> 10
            );
        }
    }
}
