//! C ABI: quality (in progress).
