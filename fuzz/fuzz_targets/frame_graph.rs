//! libFuzzer entry of the `frame_graph` target; the body is `fuzz::frame_graph::run`.
#![no_main]

#[global_allocator]
static ALLOCATOR: fuzz::alloc_limit::LimitedAllocator = fuzz::alloc_limit::LimitedAllocator;

libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzz::frame_graph::run(data));
