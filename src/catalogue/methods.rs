//! The machinery behind the catalogue's one list of methods ([`methods!`] in `mod.rs`): from
//! one entry per method it defines [`Algorithm`](super::Algorithm) with its `ALL`, `spec`,
//! `configure` and `build` dispatch, [`Config`](super::Config) with `from_json`, `json` and
//! the tile share, and each method's [`Running`](super::Running) impl, so that nothing about
//! a method is written twice and no list can miss one.

/// Defines the catalogue from its entries, in the order tables, menus and `ALL` list them.
/// Each entry, after the variant's doc comment:
///
/// - `spec`: its [`Spec`](super::Spec) (the name is the command line's and front.json's; its
///   `measures` are the error measures it makes fronts in, and `measure_note` says how, or why
///   it takes `sum` only);
/// - `params`: its params type (serde, `Default`), which [`Config`](super::Config) holds;
/// - `configure: |given| …`: its params from the caller's [`Params`](super::Params) (already
///   checked against `spec.reads` and `spec.measures`), or an error for contradicting ones; a
///   method that takes other measures copies `given.error` into its params;
/// - `build: |p, hf, seed| …`: its [`Built`](super::Built);
/// - optionally `runs: …`, the GA runs one run is made of (default 1), and
///   `tile_share: |p, points, tiles| …`, its params on one tile of `tiles` cutting a grid of
///   `points` points (default: unchanged);
/// - `running: Type { … }`: its optimizer type and the body of its `Running` impl.
macro_rules! methods {
    ($(
        $(#[doc = $doc:literal])*
        $variant:ident {
            spec: $spec:expr,
            params: $params:ty,
            configure: |$given:ident| $configure:expr,
            build: |$p:ident, $hf:ident, $seed:ident| $build:expr,
            $(runs: $runs:expr,)?
            $(tile_share: |$sp:ident, $points:ident, $tiles:ident| $share:expr,)?
            running: $optimizer:ty { $($running:tt)* } $(,)?
        }
    ),+ $(,)?) => {
        /// A method of the catalogue. Its command-line name (the variant's name in kebab case)
        /// is also the `algorithm` field of front.json and share links.
        #[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
        #[cfg_attr(not(target_arch = "wasm32"), derive(clap::ValueEnum))]
        pub enum Algorithm {
            $($(#[doc = $doc])* $variant,)+
        }

        /// A method's full parameters, as its own module takes them. It serialises as
        /// `{"algorithm": name, "params": {…}}` (see [`Config::from_json`] for reading), so a
        /// run's method travels whole to another process (a Dask worker, a Web Worker).
        #[derive(Clone, Debug, PartialEq)]
        pub enum Config {
            $(
                #[doc = concat!("[`Algorithm::", stringify!($variant), "`].")]
                $variant($params),
            )+
        }

        impl Algorithm {
            /// Every method, in the order tables, menus and `paretomesh algorithms` list them.
            pub const ALL: [Algorithm; [$(stringify!($variant)),+].len()] =
                [$(Algorithm::$variant),+];

            /// The method's fixed facts.
            pub fn spec(self) -> Spec {
                match self {
                    $(Algorithm::$variant => $spec,)+
                }
            }

            /// How many GA runs one run of the method is made of (the weighted-sum GA: one per
            /// weight), and so how many shares an equal budget is split into.
            pub(crate) fn runs_per_run(self) -> usize {
                match self {
                    $(Algorithm::$variant => methods!(@or [$($runs)?] 1),)+
                }
            }

            /// The method with its own defaults (its params type's `Default`).
            pub(crate) fn defaults(self) -> Config {
                match self {
                    $(Algorithm::$variant => Config::$variant(<$params>::default()),)+
                }
            }

            /// The method's own parameters from `given`, checked against what it reads by
            /// [`Algorithm::configure`].
            fn configure_checked(self, given: &Params) -> Result<Config, String> {
                Ok(match self {
                    $(Algorithm::$variant => {
                        let $given = given;
                        let made: Result<$params, String> = $configure;
                        Config::$variant(made?)
                    })+
                })
            }
        }

        impl Config {
            /// The method these are the parameters of.
            pub fn algorithm(&self) -> Algorithm {
                match self {
                    $(Config::$variant(_) => Algorithm::$variant,)+
                }
            }

            /// `algorithm`'s full parameters from JSON as front.json records them (`null` or
            /// any subset of the fields: the others keep the method's defaults). Errors name
            /// the field.
            pub fn from_json(
                algorithm: Algorithm,
                given: &serde_json::Value,
            ) -> Result<Config, String> {
                Ok(match algorithm {
                    $(Algorithm::$variant => {
                        Config::$variant(laid(<$params>::default(), given)?)
                    })+
                })
            }

            /// The parameters as front.json and results.json record them.
            pub(crate) fn json(&self) -> serde_json::Value {
                match self {
                    $(Config::$variant(p) => serde_json::to_value(p),)+
                }
                .expect("parameters are plain data")
            }

            /// Builds the optimizer on `hf`; `seed` drives a stochastic method. Errors: the
            /// parameters are out of range, with the method's own message.
            pub fn build(self, hf: Arc<Heightfield>, seed: u64) -> Result<Built, String> {
                match self {
                    $(Config::$variant($p) => {
                        let ($hf, $seed) = (hf, seed);
                        $build
                    })+
                }
            }

            /// The parameters each tile runs with when a grid of `points` points is cut into
            /// `tiles` tiles that each run this method (see [`crate::tiling`]).
            pub(crate) fn tile_share(self, points: u64, tiles: usize) -> Config {
                let _ = (points, tiles);
                match self {
                    $(Config::$variant(p) => Config::$variant(
                        methods!(@share p, points, tiles, [$($sp $points $tiles $share)?])
                    ),)+
                }
            }
        }

        $(impl Running for $optimizer { $($running)* })+
    };
    (@or [$given:expr] $default:expr) => { $given };
    (@or [] $default:expr) => { $default };
    (@share $p:ident, $n:ident, $k:ident, [$sp:ident $points:ident $tiles:ident $share:expr]) => {{
        let ($sp, $points, $tiles) = ($p, $n, $k);
        $share
    }};
    (@share $p:ident, $n:ident, $k:ident, []) => { $p };
}

/// `defaults` with the fields of `given` (a JSON object, or `null` for none) laid over them.
pub(super) fn laid<T: serde::Serialize + serde::de::DeserializeOwned>(
    defaults: T,
    given: &serde_json::Value,
) -> Result<T, String> {
    let mut value = serde_json::to_value(defaults).expect("parameters are plain data");
    match (value.as_object_mut(), given) {
        (_, serde_json::Value::Null) => {}
        (Some(out), serde_json::Value::Object(given)) => {
            for (k, v) in given {
                out.insert(k.clone(), v.clone());
            }
        }
        _ => value = given.clone(),
    }
    serde_json::from_value(value).map_err(|e| e.to_string())
}
