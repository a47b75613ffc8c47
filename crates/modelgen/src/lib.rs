//! The element-model generator of `fpc`: energy specs in, Rust modules out.
//!
//! `fpc-symbolic` turns a spec into kernels and knows nothing about
//! fingers. This crate knows the contract between a spec and the `fpc`
//! runtime (the prost-build pattern: generated code plugs into a runtime
//! trait) and emits, per spec, a module whose model type implements
//! `fpc`'s `ElementModel`:
//!
//! - the integrals `linear`, `prestressed` and `gas`, one per kind of block
//!   the runtime cuts from the actuator, with named parameter structs
//!   shared by every model (`LinearParams`, ...): the specs agree on the
//!   fields they share, in order, and a spec may extend a struct with
//!   trailing fields (the shear data `g13`, `ks` of `shear.spec`), which
//!   models that do not take them ignore (their kernels read the fields
//!   by name, and their tangents the leading columns);
//! - `energy = ...;`, how the integrals combine (runtime scalars in
//!   `EnergyScalars`);
//! - `scaled ...;` (the solver's unknowns) and `local ...;` (unknowns the
//!   chain does not see, condensed out of coupled systems);
//! - the point kernels the runtime reads, by role and output name:
//!   `end(L)` `{Xe, Ze, eta}`, `frame(L)` `{Xe, Ze, dx, dz}`,
//!   `midplane(x)` `{X, Z}`, `tangent(x)` `{dx, dz}`, `strain(x, z)`
//!   `{eps_x}`, `curvature(x)` `{kappa}`;
//! - the mid-plane as exact curves: `midplane(x)` must be a polynomial in
//!   `x` (its coefficients any expressions of the unknowns), and the model
//!   gets `midplane_polynomial`, the coefficients of `X(x)` and `Z(x)` in
//!   ascending powers (`ElementModel::MIDPLANE_DEGREE`,
//!   `Kinematics::midplane_coefficients`), for contacts computed on the
//!   continuous mid-plane;
//! - `law psi(s);`, the prestressed layer's material law (`PsiParams`);
//! - `across ...;`, the unknowns of the strain across the width, which
//!   plane strain holds at zero (`Across`, generated into `models.rs` so
//!   that a model's own file does not change with it);
//! - optionally `straighten t by c*s^2;`: Newton solves for `t + c s^2` in
//!   place of the unknown `t` (`Across::STRAIGHTEN`, in scaled unknowns:
//!   `t`'s scaling must be the square of `s`'s times a number, and neither
//!   may be local or across the width; docs/model.md section 4.6).
//!
//! Every rule is checked here, so a spec that breaks the contract fails the
//! build with the spec's name and the rule, never compiles into a model
//! that computes something else. Outputs: `models.rs` (the shared parameter
//! structs and the registry `ModelId`) and one `model_NAME.rs` per spec.

use std::fmt;

use fpc_symbolic::codegen::{format_file, param_structs};
use proc_macro2::{Ident, Literal, TokenStream};
use quote::quote;

/// A spec to generate a model from.
#[derive(Debug, Clone)]
pub struct SpecFile {
    /// Path relative to the package root (`energy-spec/ccm.spec`).
    pub path: String,
    /// Its text.
    pub text: String,
}

/// A generated file.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct GeneratedFile {
    /// File name inside the output directory.
    pub name: String,
    /// Its text.
    pub text: String,
}

/// Why a spec does not make a model.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{spec}: {message}")]
pub struct ModelGenError {
    /// The spec's path.
    pub spec: String,
    /// What is wrong.
    pub message: String,
}

mod contract;
mod model_file;

pub use contract::{FAMILIES, LAW, POINT_ROLES, POLYNOMIAL_ROLE};

use contract::check;
use model_file::{ident, model_file};

/// Generates every model. `default` names the model `ModelId::default()`
/// picks (its `model` name in lower case).
pub fn generate(specs: &[SpecFile], default: &str) -> Result<Vec<GeneratedFile>, ModelGenError> {
    let mut checked = Vec::new();
    for f in specs {
        checked.push(check(f)?);
    }
    if checked.is_empty() {
        return Err(ModelGenError {
            spec: "energy-spec/".into(),
            message: "no spec to generate a model from".into(),
        });
    }
    // shared parameter structs: the specs must agree on every field they
    // share, in order; a spec may extend a struct with trailing fields
    // (the shear data of a box), which models without them ignore
    let mut structs = param_structs(&checked[0].spec);
    let mut owners: Vec<usize> = vec![0; structs.len()];
    for (i, (f, c)) in specs.iter().zip(&checked).enumerate().skip(1) {
        for s in param_structs(&c.spec) {
            match structs.iter().position(|t| t.name == s.name) {
                Some(j) => {
                    let t = &structs[j];
                    let common = t.fields.len().min(s.fields.len());
                    if t.fields[..common] != s.fields[..common] {
                        return Err(ModelGenError {
                            spec: f.path.clone(),
                            message: format!(
                                "`{}` takes ({}) but {} gives it ({}): models share the runtime's parameter structs, \
                                 the same fields in the same order, a spec's extra fields last",
                                s.name,
                                s.fields.join(", "),
                                specs[owners[j]].path,
                                t.fields.join(", ")
                            ),
                        });
                    }
                    if s.fields.len() > t.fields.len() {
                        structs[j] = s;
                        owners[j] = i;
                    }
                }
                None => {
                    structs.push(s);
                    owners.push(i);
                }
            }
        }
    }
    for (i, c) in checked.iter().enumerate() {
        if checked[..i].iter().any(|d| d.module == c.module) {
            return Err(ModelGenError {
                spec: specs[i].path.clone(),
                message: format!("a second model named `{}`", c.model),
            });
        }
    }
    let default_index = checked
        .iter()
        .position(|c| c.module == default)
        .ok_or_else(|| ModelGenError {
            spec: "energy-spec/".into(),
            message: format!("the default model `{default}` has no spec"),
        })?;

    let mut files = Vec::new();
    for (f, c) in specs.iter().zip(&checked) {
        let (text, report) = model_file(f, c)?;
        files.push(GeneratedFile {
            name: format!("model_{}.rs", c.module),
            text,
        });
        files.push(GeneratedFile {
            name: format!("model_{}_report.txt", c.module),
            text: report,
        });
    }

    let struct_tokens: Vec<TokenStream> = structs.iter().map(|s| s.tokens()).collect();
    let variants: Vec<Ident> = checked.iter().map(|c| ident(&c.model)).collect();
    let modules: Vec<Ident> = checked.iter().map(|c| ident(&c.module)).collect();
    let names: Vec<&str> = checked.iter().map(|c| c.module.as_str()).collect();
    let files_rs: Vec<String> = checked
        .iter()
        .map(|c| format!("/model_{}.rs", c.module))
        .collect();
    let reports: Vec<String> = checked
        .iter()
        .map(|c| format!("/model_{}_report.txt", c.module))
        .collect();
    let default_variant = &variants[default_index];
    let across: Vec<TokenStream> = checked
        .iter()
        .map(|c| {
            let idx = c.spec.across.iter().map(|a| {
                let i = c
                    .spec
                    .unknowns
                    .iter()
                    .position(|u| u == a)
                    .expect("checked");
                Literal::usize_unsuffixed(i)
            });
            quote! { &[#(#idx),*] }
        })
        .collect();
    let straighten: Vec<TokenStream> = checked
        .iter()
        .map(|c| {
            let rows = c.straighten.iter().map(|&(t, s, k)| {
                let (t, s) = (Literal::usize_unsuffixed(t), Literal::usize_unsuffixed(s));
                let k = Literal::f64_unsuffixed(k);
                quote! { (#t, #s, #k) }
            });
            quote! { &[#(#rows),*] }
        })
        .collect();
    let generated_names: Vec<String> = files.iter().map(|f| f.name.clone()).collect();
    let model_docs: Vec<String> = specs
        .iter()
        .zip(&checked)
        .map(|(f, c)| format!("`{}`: the model of `{}`.", c.module, f.path))
        .collect();
    let tokens = quote! {
        #(#struct_tokens)*

        #(
            #[doc = #model_docs]
            #[allow(
                non_snake_case,
                unused_mut,
                clippy::too_many_arguments,
                clippy::excessive_precision,
                clippy::unreadable_literal,
                clippy::neg_multiply,
                clippy::double_parens,
                clippy::let_and_return,
                clippy::redundant_locals,
                clippy::needless_return,
                clippy::needless_late_init
            )]
            pub mod #modules {
                include!(concat!(env!("OUT_DIR"), #files_rs));

                #[doc = "The generated Rust source of this model, as compiled."]
                pub const SOURCE: &str = include_str!(concat!(env!("OUT_DIR"), #files_rs));

                #[doc = "Operation counts of its generated functions, before and after CSE."]
                pub const REPORT: &str = include_str!(concat!(env!("OUT_DIR"), #reports));
            }
        )*

        #(
            impl Across for #modules::#variants {
                const ACROSS: &'static [usize] = #across;
                const STRAIGHTEN: &'static [(usize, usize, f64)] = #straighten;
            }
        )*

        #[doc = "The element models generated from the specs in `energy-spec/`."]
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum ModelId {
            #(
                #[doc = #model_docs]
                #variants,
            )*
        }

        impl ModelId {
            #[doc = "Every model, in the order of their specs."]
            pub const ALL: &'static [ModelId] = &[#(ModelId::#variants),*];

            #[doc = "Calls the visitor with the model's type."]
            pub fn visit<V: ModelVisitor>(self, v: V) -> V::Output {
                match self {
                    #(ModelId::#variants => v.visit::<#modules::#variants>(),)*
                }
            }

            #[doc = "The generated source and its operation counts."]
            pub fn generated(self) -> (&'static str, &'static str) {
                match self {
                    #(ModelId::#variants => (#modules::SOURCE, #modules::REPORT),)*
                }
            }

            #[doc = "The model's name (lower case), as the CLI and scene files spell it."]
            pub fn name(self) -> &'static str {
                match self {
                    #(ModelId::#variants => #names,)*
                }
            }
        }

        #[doc = "Every generated file (name, text), as compiled: the golden test compares them."]
        pub const GENERATED_FILES: &[(&str, &str)] = &[
            ("models.rs", include_str!(concat!(env!("OUT_DIR"), "/models.rs"))),
            #(
                (#generated_names, include_str!(concat!(env!("OUT_DIR"), "/", #generated_names))),
            )*
        ];

        impl Default for ModelId {
            #[doc = "The default model (the paper's element)."]
            fn default() -> ModelId {
                ModelId::#default_variant
            }
        }

        #[doc = "`model_enum! { enum Name = Alias }` (or `enum Name<'a> = Alias`): an enum with one variant per model, named as in `ModelId`, each holding `Alias<Model>` (`Alias<'a, Model>`): static dispatch over the models (`match_model!`, `map_model!`, `model_of_id!`). The models are `crate::model`'s."]
        macro_rules! model_enum {
            ($(#[$attr:meta])* $vis:vis enum $name:ident = $alias:ident) => {
                $(#[$attr])*
                $vis enum $name {
                    #( #variants($alias<$crate::model::#modules::#variants>), )*
                }
            };
            ($(#[$attr:meta])* $vis:vis enum $name:ident<$lt:lifetime> = $alias:ident) => {
                $(#[$attr])*
                $vis enum $name<$lt> {
                    #( #variants($alias<$lt, $crate::model::#modules::#variants>), )*
                }
            };
        }
        pub(crate) use model_enum;

        #[doc = "`match_model!(value, Enum(binding) => body)`: `body`, with `binding` the content of the variant `value` holds, whatever the model (`Enum` made by `model_enum!`)."]
        macro_rules! match_model {
            ($value:expr, $enum:ident($binding:ident) => $body:expr) => {
                match $value {
                    #( $enum::#variants($binding) => $body, )*
                }
            };
        }
        pub(crate) use match_model;

        #[doc = "`map_model!(value, Enum(binding) => Out(body))`: the variant of `Out` of the model `value` holds, with `body` in it (`binding` as in `match_model!`)."]
        macro_rules! map_model {
            ($value:expr, $enum:ident($binding:ident) => $out:ident($body:expr)) => {
                match $value {
                    #( $enum::#variants($binding) => $out::#variants($body), )*
                }
            };
        }
        pub(crate) use map_model;

        #[doc = "`model_of_id!(id, M => Out(body))`: the variant of `Out` of the model `id` names, with `body` in it, evaluated with `M` the model's type."]
        macro_rules! model_of_id {
            ($id:expr, $model:ident => $out:ident($body:expr)) => {
                match $id {
                    #(
                        $crate::model::ModelId::#variants => {
                            type $model = $crate::model::#modules::#variants;
                            $out::#variants($body)
                        }
                    )*
                }
            };
        }
        pub(crate) use model_of_id;
    };
    let body = format_file(&tokens).map_err(|e| ModelGenError {
        spec: "energy-spec/".into(),
        message: e.to_string(),
    })?;
    let list: Vec<&str> = specs.iter().map(|s| s.path.as_str()).collect();
    files.insert(
        0,
        GeneratedFile {
            name: "models.rs".into(),
            text: format!(
                "// @generated by build.rs from {} with fpc-modelgen. Do not edit.\n\n{body}",
                list.join(", ")
            ),
        },
    );
    Ok(files)
}

impl fmt::Display for GeneratedFile {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} ({} bytes)", self.name, self.text.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const CCM: &str = include_str!("../../../energy-spec/ccm.spec");
    const MIDPLANE: &str = "point midplane(x) {\n    X = x + u;\n    Z = w;\n}";

    fn spec(text: String) -> Vec<SpecFile> {
        vec![SpecFile {
            path: "energy-spec/ccm.spec".into(),
            text,
        }]
    }

    #[test]
    fn the_shipped_spec_generates_the_midplane_coefficients() {
        assert!(CCM.contains(MIDPLANE));
        let files = generate(&spec(CCM.into()), "ccm").unwrap();
        let model = files.iter().find(|f| f.name == "model_ccm.rs").unwrap();
        assert!(model.text.contains("const MIDPLANE_DEGREE: usize = 3;"));
        assert!(model
            .text
            .contains("pub fn midplane_polynomial(k: &[f64; 4]) -> [[f64; 2]; 4]"));
    }

    #[test]
    fn a_midplane_not_polynomial_in_x_is_a_generation_error() {
        for (z, culprit) in [
            ("sqrt(1 + w)", "sqrt"),
            ("w/(1 + x)", "1 + x"),
            ("sin(c2*x)", "sin"),
        ] {
            let text = CCM.replace(
                MIDPLANE,
                &format!("point midplane(x) {{\n    X = x + u;\n    Z = {z};\n}}"),
            );
            let e = generate(&spec(text), "ccm").unwrap_err();
            assert_eq!(e.spec, "energy-spec/ccm.spec");
            assert!(
                e.message
                    .starts_with("`point midplane(x)` must be a polynomial in `x`"),
                "{e}"
            );
            assert!(e.message.contains("not a polynomial in x"), "{e}");
            assert!(e.message.contains(culprit), "{e}");
        }
    }

    const LINEAR: &str = "integral linear(x0, x1, width, z0, z1, q11, q12, q22) =";

    fn named(name: &str, text: String) -> SpecFile {
        SpecFile {
            path: format!("energy-spec/{name}.spec"),
            text,
        }
    }

    #[test]
    fn a_spec_may_extend_a_shared_struct_with_trailing_fields() {
        assert!(CCM.contains(LINEAR));
        let wide = CCM.replace("model Ccm;", "model Wide;").replace(
            LINEAR,
            "integral linear(x0, x1, width, z0, z1, q11, q12, q22, extra) =",
        );
        let alone = generate(&spec(CCM.into()), "ccm").unwrap();
        let ccm_alone = alone.iter().find(|f| f.name == "model_ccm.rs").unwrap();
        // in either order: the struct is the longer list, and the model
        // without the extra field is generated as it is alone
        for specs in [
            vec![named("ccm", CCM.into()), named("wide", wide.clone())],
            vec![named("wide", wide.clone()), named("ccm", CCM.into())],
        ] {
            let files = generate(&specs, "ccm").unwrap();
            let models = files.iter().find(|f| f.name == "models.rs").unwrap();
            assert!(models.text.contains("pub extra: f64"), "{}", models.text);
            assert!(models.text.contains("pub fn to_values(&self) -> [f64; 9]"));
            let ccm = files.iter().find(|f| f.name == "model_ccm.rs").unwrap();
            assert_eq!(ccm, ccm_alone);
        }
    }

    #[test]
    fn shared_fields_in_another_order_are_a_generation_error() {
        for (name, header) in [
            (
                "swapped",
                "integral linear(x0, x1, width, z0, z1, q12, q11, q22) =",
            ),
            (
                "inserted",
                "integral linear(x0, x1, width, z0, z1, extra, q11, q12, q22) =",
            ),
        ] {
            let other = CCM
                .replace("model Ccm;", &format!("model {};", name.to_uppercase()))
                .replace(LINEAR, header);
            let e = generate(&[named("ccm", CCM.into()), named(name, other)], "ccm").unwrap_err();
            assert_eq!(e.spec, format!("energy-spec/{name}.spec"));
            assert!(e.message.starts_with("`LinearParams` takes"), "{e}");
            assert!(e.message.contains("extra fields last"), "{e}");
        }
    }

    #[test]
    fn a_spec_names_its_unknowns_across_the_width() {
        let across = "across b1;";
        assert!(CCM.contains(across));
        let e = generate(&spec(CCM.replace(across, "")), "ccm").unwrap_err();
        assert!(
            e.message.starts_with("needs an `across ...;` statement"),
            "{e}"
        );
        let files = generate(&spec(CCM.into()), "ccm").unwrap();
        let models = files.iter().find(|f| f.name == "models.rs").unwrap();
        assert!(
            models.text.contains("impl Across for ccm::Ccm"),
            "{}",
            models.text
        );
        assert!(models
            .text
            .contains("const ACROSS: &'static [usize] = &[2];"));
    }

    #[test]
    fn newton_unknowns_are_straightened_as_the_spec_says() {
        let line = "straighten a3 by 2/3*c2^2;";
        assert!(CCM.contains(line));
        let files = generate(&spec(CCM.into()), "ccm").unwrap();
        let models = files.iter().find(|f| f.name == "models.rs").unwrap();
        // a3 is unknown 1, c2 unknown 3; scaled a3 L^2 and c2 L: the
        // scaled shift keeps the raw coefficient
        assert!(
            models.text.contains(
                "const STRAIGHTEN: &'static [(usize, usize, f64)] = &[(1, 3, 0.6666666666666666)];"
            ),
            "{}",
            models.text
        );
        // without the statement, nothing changes
        let files = generate(&spec(CCM.replace(line, "")), "ccm").unwrap();
        let models = files.iter().find(|f| f.name == "models.rs").unwrap();
        assert!(models
            .text
            .contains("const STRAIGHTEN: &'static [(usize, usize, f64)] = &[];"));
        // a3 L^2 against c2 (unscaled): no longer the square of c2's scaling
        // times a number
        let e = generate(
            &spec(CCM.replace("scaled a1, a3*L^2, b1, c2*L;", "scaled a1, a3*L^2, b1, c2;")),
            "ccm",
        )
        .unwrap_err();
        assert!(
            e.message
                .contains("needs `a3`'s scaling to be the square of `c2`'s"),
            "{e}"
        );
        // the local unknown b1 cannot take part
        let e = generate(&spec(CCM.replace(line, "straighten a1 by 2*b1^2;")), "ccm").unwrap_err();
        assert!(
            e.message
                .contains("`b1`, which is local or across the width"),
            "{e}"
        );
        // the parser's rules
        for (bad, says) in [
            (
                "straighten a3 by 2/3*c2;",
                "a nonzero number times the square of another unknown",
            ),
            (
                "straighten a3 by 2/3*a3^2;",
                "a nonzero number times the square of another unknown",
            ),
            (
                "straighten a3 by 0*c2^2;",
                "a nonzero number times the square of another unknown",
            ),
            ("straighten zz by c2^2;", "an unknown (`zz` is not one)"),
            ("straighten a3 c2^2;", "`by` and the shift"),
            (
                "straighten a3 by c2^2;\nstraighten c2 by a1^2;",
                "unknowns that no other",
            ),
        ] {
            let e = generate(&spec(CCM.replace(line, bad)), "ccm").unwrap_err();
            assert!(e.message.contains(says), "{bad}: {e}");
        }
    }

    #[test]
    fn coefficients_may_be_any_expression_of_the_unknowns() {
        // X's linear coefficient through a square root of the unknowns: still
        // a polynomial in x
        let text = CCM.replace(
            MIDPLANE,
            "point midplane(x) {\n    X = sqrt(1 + a1)*x + a3*x^3;\n    Z = w;\n}",
        );
        let files = generate(&spec(text), "ccm").unwrap();
        let model = files.iter().find(|f| f.name == "model_ccm.rs").unwrap();
        assert!(model.text.contains("const MIDPLANE_DEGREE: usize = 3;"));
    }
}
