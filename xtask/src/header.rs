//! The Fortran module's constants and `bind(C)` types, generated from the C header.
//!
//! `ffi/generated/deform_kernel.h` is cbindgen's rendering of the ffi crate's `#[repr(C)]`
//! structs and constants (written by `cargo xtask codegen` just before), so the Fortran declarations
//! are read from it rather than kept by hand: a field added, moved or retyped in Rust reaches
//! Fortran with the next `cargo xtask codegen`, and a stale Fortran layout fails
//! `cargo xtask codegen --check`. Reads only what cbindgen writes: `//` doc lines, `#define
//! NAME VALUE`, the `dk_status` enum, `typedef struct { TYPE name[N]; … } dk_name;` and the
//! names of function-pointer typedefs (`typedef R (*dk_name)(…);`, fields of `type(c_funptr)`).

/// The checked-in C header.
pub(crate) const HEADER: &str = "ffi/generated/deform_kernel.h";

/// A C declaration with the `//` doc lines above it.
struct Doc(Vec<String>);

impl Doc {
    /// The doc as Fortran comment lines at `indent`, rustdoc links unwrapped.
    fn fortran(&self, indent: &str) -> String {
        let mut out = String::new();
        for (i, line) in self.0.iter().enumerate() {
            let text = line.replace("[`", "`").replace("`]", "`");
            let mark = if i == 0 { "!>" } else { "!!" };
            if text.is_empty() {
                out += &format!("{indent}{mark}\n");
            } else {
                out += &format!("{indent}{mark} {text}\n");
            }
        }
        out
    }
}

/// The Fortran type of a C field type (`const double *` → `type(c_ptr)`, a function-pointer
/// typedef named in `funptrs` → `type(c_funptr)`).
fn fortran_field_type(c: &str, funptrs: &[String]) -> Result<String, String> {
    if c.ends_with('*') {
        return Ok("type(c_ptr)".into());
    }
    if funptrs.iter().any(|f| f == c) {
        return Ok("type(c_funptr)".into());
    }
    Ok(match c {
        "double" => "real(c_double)",
        "float" => "real(c_float)",
        "size_t" => "integer(c_size_t)",
        "int64_t" | "uint64_t" => "integer(c_int64_t)",
        "int32_t" | "uint32_t" => "integer(c_int32_t)",
        "int8_t" | "uint8_t" => "integer(c_int8_t)",
        "bool" => "logical(c_bool)",
        t if t.starts_with("dk_") => return Ok(format!("type({t})")),
        t => return Err(format!("{HEADER}: no Fortran type for C type `{t}`")),
    }
    .into())
}

/// The Fortran declaration of `#define NAME VALUE` (an integer constant), or `None` for
/// a macro that is not one (the include guard).
fn constant(name: &str, value: &str) -> Option<String> {
    if value == "(size_t)-1" {
        return Some(format!(
            "integer(c_size_t), parameter, public :: {name} = -1_c_size_t"
        ));
    }
    value.parse::<i32>().ok()?;
    Some(format!(
        "integer(c_int32_t), parameter, public :: {name} = {value}"
    ))
}

/// The generated Fortran declarations: status codes, constants, then the structs in header
/// order (so a struct is declared before a struct that contains it).
pub(crate) fn fortran_declarations(header: &str) -> Result<String, String> {
    // `typedef int32_t (*dk_name)(…);`: callback types (Fortran `type(c_funptr)`).
    let funptrs: Vec<String> = header
        .lines()
        .filter_map(|l| l.trim().strip_prefix("typedef "))
        .filter_map(|l| l.split_once("(*")?.1.split_once(')'))
        .map(|(name, _)| name.to_string())
        .collect();
    let mut status = String::new();
    let mut constants = String::new();
    let mut types = String::new();
    let mut doc: Vec<String> = Vec::new();
    let mut lines = header.lines().map(str::trim);
    while let Some(line) = lines.next() {
        if let Some(text) = line.strip_prefix("//") {
            doc.push(text.strip_prefix(' ').unwrap_or(text).to_string());
            continue;
        }
        let this = Doc(std::mem::take(&mut doc));
        if let Some(def) = line.strip_prefix("#define ") {
            let (name, value) = def.split_once(' ').unwrap_or((def, ""));
            if let Some(decl) = constant(name, value.trim()) {
                constants += &this.fortran("  ");
                constants += &format!("  {decl}\n");
            }
        } else if line == "enum dk_status" {
            for l in lines.by_ref() {
                if l == "};" {
                    break;
                }
                if let Some((name, value)) = l.trim_end_matches(',').split_once(" = ") {
                    status +=
                        &format!("  integer(c_int32_t), parameter, public :: {name} = {value}\n");
                }
            }
        } else if line == "typedef struct {" {
            let mut fields = String::new();
            let mut field_doc: Vec<String> = Vec::new();
            let name = loop {
                let l = lines
                    .next()
                    .ok_or_else(|| format!("{HEADER}: unterminated struct"))?;
                if let Some(text) = l.strip_prefix("//") {
                    field_doc.push(text.strip_prefix(' ').unwrap_or(text).to_string());
                    continue;
                }
                if let Some(name) = l.strip_prefix("} ") {
                    break name.trim_end_matches(';').to_string();
                }
                let decl = l
                    .strip_suffix(';')
                    .ok_or_else(|| format!("{HEADER}: unexpected struct line `{l}`"))?;
                let split = decl
                    .rfind([' ', '*'])
                    .ok_or_else(|| format!("{HEADER}: unexpected field `{l}`"))?;
                let (ty, field) = (decl[..=split].trim(), &decl[split + 1..]);
                let ty = ty.strip_prefix("const ").unwrap_or(ty);
                let (field, shape) = match field.split_once('[') {
                    Some((f, n)) => (f, format!("({})", n.trim_end_matches(']'))),
                    None => (field, String::new()),
                };
                fields += &Doc(std::mem::take(&mut field_doc)).fortran("    ");
                fields += &format!(
                    "    {} :: {field}{shape}\n",
                    fortran_field_type(ty, &funptrs)?
                );
            };
            types += &format!("\n{}", this.fortran("  "));
            types += &format!("  type, bind(C), public :: {name}\n{fields}  end type\n");
        }
    }
    if status.is_empty() || types.is_empty() {
        return Err(format!("{HEADER}: no dk_status enum or no structs found"));
    }
    Ok(format!(
        "  ! Status codes (C enum dk_status).\n{status}\n{constants}{types}"
    ))
}
