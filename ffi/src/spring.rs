//! C ABI: spring (in progress).
