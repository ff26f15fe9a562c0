//! `deform_kernel._native`: the Rust half of the Python package `deform_kernel` (PyO3, abi3).
//!
//! The Python half (`deform_kernel/__init__.py`) checks dtypes, shapes, contiguity, finiteness
//! and index ranges and converts meshio-style cell blocks; this module receives contiguous
//! numpy arrays, calls the kernel's public API with the GIL released, and returns new arrays.
//! Kernel errors become `deform_kernel.KernelError` (a `ValueError`) with the kernel's message
//! and, where the kernel names them, the argument (`arg`) and index (`position`).

mod motion;
mod plan;
mod quality;
mod read;
mod smooth;

use deform_cli::error::CliError;
use deform_cli::formats::CellList;
use numpy::prelude::*;
use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::create_exception;
use pyo3::exceptions::{PyNotImplementedError, PyValueError};
use pyo3::prelude::*;

create_exception!(
    _native,
    KernelError,
    PyValueError,
    "A typed error of deform-kernel: `kind` (the variant), `arg` (the argument it names, or \
     None) and `position` (the index within that argument, or None)."
);

/// The variant name, argument and position of a kernel error.
fn error_parts(e: &deform_kernel::Error) -> (&'static str, Option<&'static str>, Option<usize>) {
    use deform_kernel::Error as E;
    match *e {
        E::LengthMismatch { arg, .. } => ("LengthMismatch", Some(arg), None),
        E::BufferTooSmall { arg, .. } => ("BufferTooSmall", Some(arg), None),
        E::IndexOutOfRange { arg, position, .. } => ("IndexOutOfRange", Some(arg), Some(position)),
        E::TooLarge { arg, .. } => ("TooLarge", Some(arg), None),
        E::BadOffsets { arg, position } => ("BadOffsets", Some(arg), Some(position)),
        E::NonFinite { arg, position } => ("NonFinite", Some(arg), Some(position)),
        E::InvalidParameter { arg, .. } => ("InvalidParameter", Some(arg), None),
        E::ZeroLength { arg, position } => ("ZeroLength", Some(arg), Some(position)),
        E::BadDimensions { arg } => ("BadDimensions", Some(arg), None),
        E::DuplicateNode { arg, position, .. } => ("DuplicateNode", Some(arg), Some(position)),
        E::NonPositive { arg, position } => ("NonPositive", Some(arg), Some(position)),
        E::Overflow { arg } => ("Overflow", Some(arg), None),
        E::NotUnit { arg, position } => ("NotUnit", Some(arg), Some(position)),
        E::NotPlanar { arg, position } => ("NotPlanar", Some(arg), Some(position)),
        E::UnknownCellKind { cell, .. }
        | E::WrongNodeCount { cell, .. }
        | E::RepeatedNode { cell, .. }
        | E::CellDimension { cell, .. } => ("Cell", Some("cells"), Some(cell)),
        E::SelfLoop { node }
        | E::SingularNode { node }
        | E::Unanchored { node }
        | E::IsolatedNode { node } => ("Node", None, Some(node)),
        _ => ("Other", None, None),
    }
}

/// A kernel error as a `KernelError` with `kind`, `arg` and `position` attributes; `context`
/// says which step failed.
pub(crate) fn kernel_error(context: &str, e: deform_kernel::Error) -> PyErr {
    let (kind, arg, position) = error_parts(&e);
    let err = KernelError::new_err(format!("{context}: {e}"));
    Python::attach(|py| {
        let v = err.value(py);
        // Setting attributes on a fresh exception instance cannot fail in practice; if it
        // did, the message still carries everything.
        let _ = v.setattr("kind", kind);
        let _ = v.setattr("arg", arg);
        let _ = v.setattr("position", position);
    });
    err
}

/// Cells in the kernel's CSR form, borrowed from numpy: `(offsets, nodes, kinds)`.
pub(crate) type Csr<'py> = (
    PyReadonlyArray1<'py, u32>,
    PyReadonlyArray1<'py, u32>,
    PyReadonlyArray1<'py, u8>,
);

/// An owned copy of CSR cells (so the work can run without the GIL).
pub(crate) fn cell_list((offsets, nodes, kinds): &Csr<'_>) -> PyResult<CellList> {
    Ok(CellList {
        offsets: offsets.as_slice()?.to_vec(),
        nodes: nodes.as_slice()?.to_vec(),
        kinds: kinds.as_slice()?.to_vec(),
    })
}

/// An error of the tool's engine as a Python exception: kernel errors as `KernelError` (with
/// the kernel's variant, argument and position), unconverged solves as `KernelError`, inputs
/// that do not fit together as `ValueError`, a missing feature as `NotImplementedError`.
pub(crate) fn cli_error(e: CliError) -> PyErr {
    match e {
        CliError::Kernel { context, source } => kernel_error(&context, source),
        CliError::Invalid(m) => PyValueError::new_err(m),
        CliError::NotAvailable { feature, needs } => {
            PyNotImplementedError::new_err(format!("{feature} needs {needs}"))
        }
        e @ (CliError::Unconverged(_) | CliError::Folded(_)) => KernelError::new_err(e.to_string()),
        e => PyValueError::new_err(e.to_string()),
    }
}

/// The edge graph of `cells` (no diagonals) as owned CSR `(offsets, targets)`.
pub(crate) fn edge_graph(
    cells: &deform_kernel::Cells<'_>,
) -> Result<(Vec<u32>, Vec<u32>), deform_kernel::Error> {
    let n = cells.node_count();
    let mut offsets = vec![0u32; n + 1];
    let mut targets = vec![0u32; deform_kernel::graph_from_cells_len(cells, false)];
    let used = deform_kernel::graph_from_cells(cells, false, &mut offsets, &mut targets)?;
    targets.truncate(used);
    Ok((offsets, targets))
}

/// Row-major `(n, d)` points as `[f64; D]` rows.
pub(crate) fn rows<const D: usize>(flat: &[f64]) -> Vec<[f64; D]> {
    flat.chunks_exact(D)
        .map(|c| core::array::from_fn(|k| c[k]))
        .collect()
}

/// `[f64; D]` rows as an `(n, D)` numpy array that takes over the vector's buffer (no copy).
pub(crate) fn to_numpy<const D: usize>(
    py: Python<'_>,
    rows: Vec<[f64; D]>,
) -> PyResult<Bound<'_, PyAny>> {
    let n = rows.len();
    Ok(PyArray1::from_vec(py, rows.into_flattened())
        .reshape([n, D])?
        .into_any())
}

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("KernelError", m.py().get_type::<KernelError>())?;
    m.add_function(wrap_pyfunction!(motion::move_points, m)?)?;
    m.add_function(wrap_pyfunction!(quality::cell_quality, m)?)?;
    m.add_function(wrap_pyfunction!(smooth::smooth_block, m)?)?;
    m.add_function(wrap_pyfunction!(smooth::smooth_mesh_graph, m)?)?;
    m.add_function(wrap_pyfunction!(read::read_su2, m)?)?;
    m.add_function(wrap_pyfunction!(read::read_plot3d, m)?)?;
    m.add_class::<plan::NativePlan>()?;
    Ok(())
}
