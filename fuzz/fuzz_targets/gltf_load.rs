//! libFuzzer entry of the `gltf_load` target; the body is `fuzz::gltf_load::run`. Half of the
//! mutations are structure-aware (`fuzz::gltf_mutate`: edits of the JSON chunk's counts,
//! offsets, indices, component types and node children), half are libFuzzer's byte mutations.
#![no_main]

#[global_allocator]
static ALLOCATOR: fuzz::alloc_limit::LimitedAllocator = fuzz::alloc_limit::LimitedAllocator;

libfuzzer_sys::fuzz_target!(|data: &[u8]| fuzz::gltf_load::run(data));

libfuzzer_sys::fuzz_mutator!(|data: &mut [u8], size: usize, max_size: usize, seed: u32| {
    if seed % 2 == 0
        && let Some(mutated) = fuzz::gltf_mutate::mutate(&data[..size], seed)
        && mutated.len() <= max_size
    {
        data[..mutated.len()].copy_from_slice(&mutated);
        return mutated.len();
    }
    libfuzzer_sys::fuzzer_mutate(data, size, max_size)
});
