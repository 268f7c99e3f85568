//! The curated demo links: the page's "Examples" and the README's list
//! (`app/tests/logic.rs` checks the README carries exactly these links).
//!
//! Each is an ordinary share link ([`super::share`]) on a built-in surface, so opening one
//! re-runs the algorithm in the page. The selected indices were picked from the CLI's fronts
//! for the same settings (`paretomesh run tests/data/NAME.f32 --algo … --seed …`), where they
//! show a mesh of a few hundred triangles.

use super::algorithms::{Algorithm, Params};
use super::camera::OrbitCamera;
use super::share::{ShareLink, SharedSurface, ViewToggles};

/// A curated demo link.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Example {
    /// Short title for the page and the README.
    pub title: &'static str,
    /// One sentence on what it shows.
    pub description: &'static str,
    /// The link itself.
    pub link: ShareLink,
}

fn nsga2(population: usize, generations: usize, seed: u64) -> Params {
    Params {
        population,
        generations,
        seed,
        ..Params::default()
    }
}

fn camera(yaw: f32, pitch: f32, distance: f32) -> OrbitCamera {
    OrbitCamera {
        yaw,
        pitch,
        distance,
        ..OrbitCamera::default()
    }
}

/// The curated examples, in the page's order.
pub(crate) fn examples() -> Vec<Example> {
    vec![
        Example {
            title: "Terrain, the paper's run",
            description: "NSGA-II with orthogonal-array crossover and the paper's settings \
                          (population 100, 50 generations) on the Jacksboro fault DEM; a \
                          562-triangle mesh selected, its error map shown.",
            link: ShareLink {
                surface: SharedSurface::Builtin("jacksboro_65x65".into()),
                algorithm: Algorithm::Nsga2,
                params: nsga2(100, 50, 1),
                generations_run: 50,
                selected: Some(70),
                camera: camera(-2.2, 0.75, 1.8),
                toggles: ViewToggles {
                    error: true,
                    ..ViewToggles::default()
                },
            },
        },
        Example {
            title: "Face-like relief",
            description: "NSGA-II (population 60, 30 generations) on the cameraman photo read as \
                          heights; a 433-triangle mesh with its kept vertices.",
            link: ShareLink {
                surface: SharedSurface::Builtin("camera_65x65".into()),
                algorithm: Algorithm::Nsga2,
                params: nsga2(60, 30, 3),
                generations_run: 30,
                selected: Some(45),
                camera: camera(-1.57, 1.2, 1.7),
                toggles: ViewToggles {
                    kept: true,
                    ..ViewToggles::default()
                },
            },
        },
        Example {
            title: "Range scan, a quick run",
            description: "NSGA-II (population 40, 20 generations, a few seconds) on the range \
                          image of the Stanford bunny; a 129-triangle mesh over the original \
                          surface.",
            link: ShareLink {
                surface: SharedSurface::Builtin("bunny_65x65".into()),
                algorithm: Algorithm::Nsga2,
                params: nsga2(40, 20, 7),
                generations_run: 20,
                selected: Some(30),
                camera: camera(-1.9, 0.9, 1.9),
                toggles: ViewToggles {
                    original: true,
                    ..ViewToggles::default()
                },
            },
        },
        Example {
            title: "Volcano, greedy insertion",
            description: "Greedy insertion (Garland & Heckbert), the strongest classical method, \
                          on the Maunga Whau DEM; a 348-triangle mesh and its error map.",
            link: ShareLink {
                surface: SharedSurface::Builtin("volcano_87x61".into()),
                algorithm: Algorithm::Greedy,
                params: Params::default(),
                // Greedy records 64 meshes; the re-run stops when it is done anyway.
                generations_run: 64,
                selected: Some(25),
                camera: camera(-2.6, 0.8, 1.8),
                toggles: ViewToggles {
                    error: true,
                    ..ViewToggles::default()
                },
            },
        },
    ]
}
