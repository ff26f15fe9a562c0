//! Golden vectors: canonical inputs, the code that runs the kernel on them, and the committed
//! hashes of all output bits. `no_std`, so the Cortex-M suite checks the same constants.
#![no_std]
