//! libFuzzer entry of the `frame_graph` target; the body is `fuzz::frame_graph::run`.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzz::frame_graph::run(data));
