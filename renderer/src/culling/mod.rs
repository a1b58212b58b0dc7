//! Light culling: which lights (and later decals and probes) can touch each screen tile or
//! froxel cluster.
//!
//! The GPU kernels live in `shaders_gen`; this module holds the host side and the independent CPU
//! reference ([`reference`]) that the kernels are proven against.

pub mod reference;
