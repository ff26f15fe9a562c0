//! `#[export(...)]`: marks an item of `deform-kernel-ffi` that `cargo xtask codegen` exports
//! to C. The attribute changes nothing (it returns the item as written); the generator reads
//! it with `syn` from the source.
//!
//! On a function `fn quat_mul` it means "export `dk_quat_mul`"; its arguments:
//! - `twin`: also `dk_quat_mul_f32` (the function is generic over `T: Real`);
//! - `name[N]`: the pointer argument `name` is read for `N` elements, without a `name_len`
//!   argument (`[1]` is one value or struct, a Fortran scalar);
//! - `name?`: the pointer `name` may be NULL (Fortran passes `type(c_ptr)`).
//!
//! An argument `_dim: Dim<D>` or `_components: Components<V>` needs no marker: it is a
//! `uint32_t` in C that picks the instance of the const parameter.
//!
//! On a `#[repr(C)]` struct generic over the real type, `#[export(twin = dk_name)]` names its
//! two C structs `dk_name` (f64) and `dk_name_f32`.

use proc_macro::TokenStream;

/// The inert export marker (see the crate documentation).
#[proc_macro_attribute]
pub fn export(_args: TokenStream, item: TokenStream) -> TokenStream {
    item
}
