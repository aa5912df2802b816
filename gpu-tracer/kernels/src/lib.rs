//! Compute kernels: thin `#[spirv]` entry points over plain functions that
//! also run on the host.
#![cfg_attr(target_arch = "spirv", no_std)]
