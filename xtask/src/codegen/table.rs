//! The C ABI as the ffi crate's source declares it: every item marked `#[export(...)]` in
//! `ffi/src/<module>.rs`, read with `syn` (the marker itself is inert, see
//! `ffi/export-macro`).

use std::path::Path;

use proc_macro2::{Delimiter, TokenStream, TokenTree};
use quote::ToTokens;

/// How a parameter crosses the ABI.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    /// `In<'_, E>`: a `*const E` (read).
    In,
    /// `Out<'_, E>`: a `*mut E` (written).
    Out,
    /// Passed by value.
    Value,
}

/// One parameter of an exported function.
pub(crate) struct Param {
    pub(crate) name: String,
    /// The element type of a pointer, or the value type, as tokens separated by spaces
    /// (`T` is the real type of a twin).
    pub(crate) ty: String,
    pub(crate) kind: Kind,
    /// `name[N]`: elements promised at a pointer without a `_len` argument.
    pub(crate) cap: Option<String>,
    /// `name?`: may be NULL (Fortran passes `type(c_ptr)`).
    pub(crate) nullable: bool,
    /// `_dim: Dim<D>` or `_components: Components<V>`: a `uint32_t` in C (named without the
    /// underscore) whose value the wrapper turns into the const parameter.
    pub(crate) dispatch: Option<Dispatch>,
}

/// A C argument that selects an instance of a function generic over a const parameter.
#[derive(Clone)]
pub(crate) struct Dispatch {
    /// The Rust marker type (`Dim`, `Components`), also the value the wrapper passes.
    pub(crate) marker: &'static str,
    /// The const parameter it sets.
    pub(crate) generic: String,
    /// The values the C argument may take; any other is `DK_ERR_INVALID_PARAMETER`.
    pub(crate) values: std::ops::RangeInclusive<u32>,
}

/// A generic parameter of an exported function, in order: the real type of a twin, or a
/// const parameter set by a [`Dispatch`] argument.
#[derive(Clone, PartialEq, Eq)]
pub(crate) enum Generic {
    Real,
    Const(String),
}

impl Param {
    /// A pointer followed by its `_len` argument.
    pub(crate) fn has_len(&self) -> bool {
        self.kind != Kind::Value && self.cap.is_none()
    }
}

/// What an exported function returns.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(crate) enum Ret {
    /// `dk_status`.
    Status,
    /// `&'static CStr`, returned to C as `const char *`.
    CStr,
}

/// One exported function (`fn dk_quat_mul` exports `dk_quat_mul`, and with `twin` also
/// `dk_quat_mul_f32`).
pub(crate) struct Func {
    /// The name of the safe function, which is the C name of the f64 function.
    pub(crate) rust: String,
    pub(crate) twin: bool,
    /// Doc lines (`///…`) of the f64 function.
    pub(crate) doc: Vec<String>,
    /// Doc lines of the twin's first paragraph (the `# f32 twin` section), if any.
    pub(crate) doc32: Vec<String>,
    pub(crate) params: Vec<Param>,
    pub(crate) ret: Ret,
    /// Returns `Result<(), dk_status>` (the wrapper maps `Ok` to `DK_OK`) rather than a status.
    pub(crate) result: bool,
    /// The generic parameters, in order.
    pub(crate) generics: Vec<Generic>,
}

impl Func {
    /// The C name of the f64 function.
    pub(crate) fn c_name(&self) -> String {
        self.rust.clone()
    }

    /// The C names with their precision (`None` for a function without a twin).
    pub(crate) fn variants(&self) -> Vec<(String, Prec)> {
        let mut v = vec![(self.c_name(), F64)];
        if self.twin {
            v.push((format!("{}_f32", self.c_name()), F32));
        }
        v
    }
}

/// A `#[repr(C)]` struct generic over the real type with its two C names.
pub(crate) struct TwinStruct {
    pub(crate) rust: String,
    pub(crate) c: String,
}

/// The exports of one module of `ffi/src`.
pub(crate) struct Module {
    pub(crate) name: String,
    /// The module's `//!` doc lines.
    pub(crate) doc: Vec<String>,
    pub(crate) funcs: Vec<Func>,
    pub(crate) structs: Vec<TwinStruct>,
    /// The public types the module defines (structs, enums, type aliases).
    pub(crate) types: Vec<String>,
    /// The names it re-exports (`pub use`), visible here through `imp`.
    pub(crate) reexports: Vec<String>,
}

/// A precision: the real type and the C name suffix.
#[derive(Clone, Copy)]
pub(crate) struct Prec {
    pub(crate) real: &'static str,
    pub(crate) suffix: &'static str,
}

pub(crate) const F64: Prec = Prec {
    real: "f64",
    suffix: "",
};
pub(crate) const F32: Prec = Prec {
    real: "f32",
    suffix: "_f32",
};

impl Prec {
    /// `ty` (tokens separated by spaces) with `T` replaced by this real type.
    pub(crate) fn expand(self, ty: &str) -> String {
        ty.split(' ')
            .map(|w| if w == "T" { self.real } else { w })
            .collect::<Vec<_>>()
            .join(" ")
    }
}

/// The modules of `ffi/src/lib.rs` (`pub mod NAME;`, in order) that export something: each
/// is `ffi/generated/NAME.rs`, whose child `imp` is the hand-kept `ffi/src/NAME.rs`.
pub(crate) fn read(ffi: &Path) -> Result<Vec<Module>, String> {
    let lib = read_text(&ffi.join("src/lib.rs"))?;
    let mut modules = Vec::new();
    for line in lib.lines() {
        let Some(name) = line
            .strip_prefix("pub mod ")
            .and_then(|r| r.strip_suffix(';'))
        else {
            continue;
        };
        let path = ffi.join(format!("src/{name}.rs"));
        let m = module(name, &read_text(&path)?).map_err(|e| format!("{}: {e}", path.display()))?;
        if !m.funcs.is_empty() || !m.structs.is_empty() {
            modules.push(m);
        }
    }
    Ok(modules)
}

pub(crate) fn read_text(path: &Path) -> Result<String, String> {
    std::fs::read_to_string(path).map_err(|e| format!("{}: {e}", path.display()))
}

fn module(name: &str, text: &str) -> Result<Module, String> {
    let file = syn::parse_file(text).map_err(|e| e.to_string())?;
    let mut m = Module {
        name: name.to_string(),
        doc: text
            .lines()
            .take_while(|l| l.starts_with("//!"))
            .map(str::to_string)
            .collect(),
        funcs: Vec::new(),
        structs: Vec::new(),
        types: Vec::new(),
        reexports: Vec::new(),
    };
    for item in &file.items {
        match item {
            syn::Item::Fn(f) => {
                if let Some(marks) = marker(&f.attrs)? {
                    m.funcs.push(func(f, &marks)?);
                }
            }
            syn::Item::Use(u) if matches!(u.vis, syn::Visibility::Public(_)) => {
                let text = u.tree.to_token_stream().to_string();
                m.reexports.extend(
                    text.split([' ', ',', '{', '}', ':'])
                        .filter(|w| !w.is_empty())
                        .map(str::to_string),
                );
            }
            syn::Item::Enum(e) if matches!(e.vis, syn::Visibility::Public(_)) => {
                m.types.push(e.ident.to_string());
            }
            syn::Item::Struct(s) => {
                if matches!(s.vis, syn::Visibility::Public(_)) {
                    m.types.push(s.ident.to_string());
                }
                if let Some(marks) = marker(&s.attrs)? {
                    let c = marks
                        .iter()
                        .find_map(|k| match k {
                            Mark::TwinStruct(c) => Some(c.clone()),
                            _ => None,
                        })
                        .ok_or_else(|| format!("struct {}: expected `twin = dk_name`", s.ident))?;
                    m.structs.push(TwinStruct {
                        rust: s.ident.to_string(),
                        c,
                    });
                }
            }
            _ => {}
        }
    }
    Ok(m)
}

/// One argument of the marker.
enum Mark {
    Twin,
    TwinStruct(String),
    Cap(String, String),
    Nullable(String),
}

/// The arguments of the `#[export(...)]` attribute, if there is one.
fn marker(attrs: &[syn::Attribute]) -> Result<Option<Vec<Mark>>, String> {
    let Some(attr) = attrs.iter().find(|a| a.path().is_ident("export")) else {
        return Ok(None);
    };
    let tokens = match &attr.meta {
        syn::Meta::Path(_) => TokenStream::new(),
        syn::Meta::List(l) => l.tokens.clone(),
        syn::Meta::NameValue(_) => return Err("`#[export = …]` is not a marker".into()),
    };
    let mut marks = Vec::new();
    let all: Vec<TokenTree> = tokens.into_iter().collect();
    for part in all.split(|t| matches!(t, TokenTree::Punct(p) if p.as_char() == ',')) {
        let text: Vec<String> = part.iter().map(ToString::to_string).collect();
        let mark = match part {
            [] => continue,
            [TokenTree::Ident(i)] if i == "twin" => Mark::Twin,
            [TokenTree::Ident(i), TokenTree::Punct(p), TokenTree::Ident(c)]
                if i == "twin" && p.as_char() == '=' =>
            {
                Mark::TwinStruct(c.to_string())
            }
            [TokenTree::Ident(i), TokenTree::Group(g)] if g.delimiter() == Delimiter::Bracket => {
                Mark::Cap(i.to_string(), g.stream().to_string())
            }
            [TokenTree::Ident(i), TokenTree::Punct(p)] if p.as_char() == '?' => {
                Mark::Nullable(i.to_string())
            }
            _ => return Err(format!("unknown `#[export]` argument `{}`", text.join(" "))),
        };
        marks.push(mark);
    }
    Ok(Some(marks))
}

fn func(f: &syn::ItemFn, marks: &[Mark]) -> Result<Func, String> {
    let rust = f.sig.ident.to_string();
    let err = |what: &str| format!("fn {rust}: {what}");
    let mut doc = Vec::new();
    let mut doc32 = Vec::new();
    for a in &f.attrs {
        if let syn::Meta::NameValue(nv) = &a.meta {
            if nv.path.is_ident("doc") {
                if let syn::Expr::Lit(syn::ExprLit {
                    lit: syn::Lit::Str(s),
                    ..
                }) = &nv.value
                {
                    let line = format!("///{}", s.value());
                    if line == "/// # Safety" {
                        return Err(err(
                            "has a `# Safety` section: codegen writes it from the signature \
                             and markers (say anything more in the description)",
                        ));
                    }
                    if line == "/// # f32 twin" || !doc32.is_empty() {
                        doc32.push(line);
                    } else {
                        doc.push(line);
                    }
                }
            }
        }
    }
    if !doc32.is_empty() {
        doc32.remove(0);
        while doc.last().is_some_and(|l| l == "///") {
            doc.pop();
        }
    }
    let (ret, result) = match &f.sig.output {
        syn::ReturnType::Type(_, t) => match t.to_token_stream().to_string().as_str() {
            "dk_status" => (Ret::Status, false),
            "Result < () , dk_status >" => (Ret::Status, true),
            "& 'static core :: ffi :: CStr" => (Ret::CStr, false),
            t => return Err(err(&format!("returns `{t}`, not `dk_status`"))),
        },
        syn::ReturnType::Default => return Err(err("returns nothing")),
    };
    let mut params = Vec::new();
    for input in &f.sig.inputs {
        let syn::FnArg::Typed(pt) = input else {
            return Err(err("takes self"));
        };
        let mut name = pt.pat.to_token_stream().to_string();
        let (kind, mut ty) = token_type(&pt.ty);
        let dispatch = dispatch(&pt.ty);
        if dispatch.is_some() {
            name = name.trim_start_matches('_').to_string();
            ty = "u32".into();
        }
        params.push(Param {
            dispatch,
            cap: marks.iter().find_map(|m| match m {
                Mark::Cap(n, c) if *n == name => Some(c.clone()),
                _ => None,
            }),
            nullable: marks
                .iter()
                .any(|m| matches!(m, Mark::Nullable(n) if *n == name)),
            name,
            ty,
            kind,
        });
    }
    for m in marks {
        if let Mark::Cap(n, _) | Mark::Nullable(n) = m {
            if !params.iter().any(|p| p.name == *n && p.kind != Kind::Value) {
                return Err(err(&format!(
                    "the marker names `{n}`, not a pointer argument"
                )));
            }
        }
    }
    let twin = marks.iter().any(|m| matches!(m, Mark::Twin));
    if twin != (f.sig.generics.type_params().count() == 1) {
        return Err(err(
            "a `twin` has one type parameter (the real type `T`), others none",
        ));
    }
    let mut generics = Vec::new();
    for g in &f.sig.generics.params {
        match g {
            syn::GenericParam::Type(_) => generics.push(Generic::Real),
            syn::GenericParam::Const(c) => {
                let n = c.ident.to_string();
                let set = params
                    .iter()
                    .filter(|p| p.dispatch.as_ref().is_some_and(|d| d.generic == n));
                if set.count() != 1 {
                    return Err(err(&format!(
                        "no one `Dim<{n}>`/`Components<{n}>` sets `{n}`"
                    )));
                }
                generics.push(Generic::Const(n));
            }
            syn::GenericParam::Lifetime(_) => {}
        }
    }
    Ok(Func {
        rust,
        twin,
        doc,
        doc32,
        params,
        ret,
        result,
        generics,
    })
}

/// `Dim<D>` (2 or 3) or `Components<V>` (1 to 7): the C argument that picks the instance.
fn dispatch(ty: &syn::Type) -> Option<Dispatch> {
    let syn::Type::Path(p) = ty else { return None };
    let last = p.path.segments.last()?;
    let (marker, values) = match last.ident.to_string().as_str() {
        "Dim" => ("Dim", 2..=3),
        "Components" => ("Components", 1..=7),
        _ => return None,
    };
    let syn::PathArguments::AngleBracketed(a) = &last.arguments else {
        return None;
    };
    let generic = a.args.first()?.to_token_stream().to_string();
    Some(Dispatch {
        marker,
        generic,
        values,
    })
}

/// `In<'_, E>` → (In, E), `Out<'_, E>` → (Out, E), anything else → (Value, it).
fn token_type(ty: &syn::Type) -> (Kind, String) {
    if let syn::Type::Path(p) = ty {
        if let Some(last) = p.path.segments.last() {
            let kind = match last.ident.to_string().as_str() {
                "In" => Some(Kind::In),
                "Out" => Some(Kind::Out),
                _ => None,
            };
            if let (Some(kind), syn::PathArguments::AngleBracketed(a)) = (kind, &last.arguments) {
                if let Some(syn::GenericArgument::Type(t)) = a.args.last() {
                    return (kind, t.to_token_stream().to_string());
                }
            }
        }
    }
    (Kind::Value, ty.to_token_stream().to_string())
}
