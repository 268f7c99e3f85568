//! The page side of share links: the Share button, opening a link (at start, from the
//! Examples, or when the hash changes), waiting for the file a link names, and the surface menu.
//!
//! A link is applied in this order: its surface is loaded, its algorithm and parameters are
//! written into the form, its camera and toggles are set, and the run is re-done from scratch
//! to the link's generation ([`App::reproduce`]), which then selects the link's front index.
//! A link that cannot be read leaves the page as it was (at start: the default demo) and says
//! why; nothing of the user's work is lost.

use super::dom::{self, by_id};
use super::page::{Ui, on_event};
use crate::app::camera::OrbitCamera;
use crate::app::examples::examples;
use crate::app::loader::{self, BUILTINS, Builtin};
use crate::app::share::{
    self, EmbeddedGrid, FileFingerprint, ImportChoice, MAX_EMBEDDED_SIDE, Origin, ShareLink,
    SharedSurface, embeddable,
};
use crate::app::state::{App, Reproduction, RunConfig, Surface};
use crate::heightfield::Heightfield;
use std::sync::Arc;
use wasm_bindgen::JsCast;
use web_sys::{HtmlInputElement, HtmlSelectElement};

/// The page's URL with `fragment` as its hash.
fn url_with_hash(fragment: &str) -> String {
    let location = web_sys::window().map(|w| w.location());
    let base = location
        .and_then(|l| {
            Some(format!(
                "{}{}{}",
                l.origin().ok()?,
                l.pathname().ok()?,
                l.search().ok()?
            ))
        })
        .unwrap_or_default();
    format!("{base}#{fragment}")
}

/// Puts `fragment` in the address bar without firing `hashchange` (which would re-open it).
fn replace_hash(fragment: &str) {
    if let Some(history) = web_sys::window().and_then(|w| w.history().ok()) {
        let _ = history.replace_state_with_url(
            &wasm_bindgen::JsValue::NULL,
            "",
            Some(&url_with_hash(fragment)),
        );
    }
}

/// The share link of what the page shows now.
fn current_link(ui: &Ui, embed: bool) -> Result<(ShareLink, String), String> {
    let surface = ui.app.surface();
    let hf = &surface.heightfield;
    let mut note = String::new();
    let shared = match (&ui.origin, embed) {
        (Origin::Builtin(name), _) => SharedSurface::Builtin((*name).to_string()),
        (Origin::File(_) | Origin::Embedded, true) | (Origin::Embedded, false) => {
            let (grid, exact) = EmbeddedGrid::of(&surface.name, hf).ok_or_else(|| {
                format!(
                    "only grids of at most {MAX_EMBEDDED_SIDE}×{MAX_EMBEDDED_SIDE} points can \
                     travel in a link; this one is {}×{}",
                    hf.width(),
                    hf.height()
                )
            })?;
            if !exact {
                note = " Heights travel as 32-bit floats, so the reader's numbers may \
                        differ slightly."
                    .to_string();
            }
            SharedSurface::Embedded(Box::new(grid))
        }
        (Origin::File(fingerprint), false) => {
            note = format!(
                " The reader must drop your file {} ({} bytes) to open it.",
                fingerprint.name, fingerprint.size
            );
            SharedSurface::File(fingerprint.clone())
        }
    };
    let status = ui.app.status();
    let config = ui.app.config();
    if status.evaluations > 0 && !status.done && ui.app.is_running() {
        note.push_str(&format!(
            " The run is still going: the link reproduces it as of generation {}.",
            status.generation
        ));
    }
    let link = ShareLink {
        surface: shared,
        algorithm: config.algorithm,
        params: config.params.clone(),
        generations_run: status.generation,
        selected: ui.app.selected_front_index(),
        camera: ui.camera,
        toggles: ui.toggles(),
    };
    Ok((link, note))
}

/// The Share button: writes the link into the box and the address bar and copies it.
pub(super) fn share(ui: &mut Ui) {
    let message = match current_link(ui, dom::checked("share-embed")) {
        Ok((link, note)) => publish(&link, &note),
        Err(e) => format!("Cannot share: {e}."),
    };
    dom::set_text("share-message", &message);
}

/// Puts `link` in the box and the address bar and copies it; returns the message to show.
fn publish(link: &ShareLink, note: &str) -> String {
    let fragment = share::encode(link);
    // Refuse to hand out a link the reader would refuse.
    if let Err(e) = share::decode(&fragment) {
        return e.to_string();
    }
    let url = url_with_hash(&fragment);
    replace_hash(&fragment);
    if let Ok(input) = by_id::<HtmlInputElement>("share-url") {
        input.set_value(&url);
        input.set_hidden(false);
        input.select();
    }
    let whereabouts = if copy_to_clipboard(&url) {
        "copied to the clipboard; it is also in the box below"
    } else {
        "in the box below: copy it from there"
    };
    format!("Link ({} characters) {whereabouts}.{note}", url.len())
}

/// Starts copying `text` to the clipboard; false when the page has no clipboard. Access can
/// still be refused later (permissions, no focus): the share message then says so.
fn copy_to_clipboard(text: &str) -> bool {
    let Some(promise) = web_sys::window().map(|w| w.navigator().clipboard().write_text(text))
    else {
        return false;
    };
    wasm_bindgen_futures::spawn_local(async move {
        if wasm_bindgen_futures::JsFuture::from(promise).await.is_err() {
            dom::set_text(
                "share-message",
                "The browser refused clipboard access: copy the link from the box below.",
            );
        }
    });
    true
}

/// Enables "embed the grid" only when the grid is small enough to travel.
pub(super) fn update_share_controls(ui: &Ui) {
    let hf = &ui.app.surface().heightfield;
    let can_embed = !matches!(ui.origin, Origin::Builtin(_)) && embeddable(hf).is_some();
    if let Ok(input) = by_id::<HtmlInputElement>("share-embed") {
        input.set_disabled(!can_embed);
        if !can_embed {
            input.set_checked(false);
        }
    }
    if let Ok(select) = by_id::<HtmlSelectElement>("surface") {
        select.set_value(match ui.origin {
            Origin::Builtin(name) => name,
            _ => "",
        });
    }
}

/// Opens the link in `fragment` (a URL hash; empty does nothing). A link that cannot be
/// read leaves everything as it is and says why.
pub(super) fn open_link(ui: &mut Ui, fragment: &str) {
    let fragment = fragment.strip_prefix('#').unwrap_or(fragment);
    if fragment.is_empty() {
        return;
    }
    let link = match share::decode(fragment) {
        Ok(link) => link,
        Err(e) => {
            let shown = if ui.app.front().is_none()
                && matches!(ui.origin, Origin::Builtin(n) if n == loader::BUILTIN_NAME)
            {
                "the default demo is shown instead"
            } else {
                "the page stays as it was"
            };
            dom::show_load_message(&format!("{e} ({shown})"), true);
            return;
        }
    };
    ui.waiting_for = None;
    match &link.surface {
        SharedSurface::Builtin(name) => {
            let Some(builtin) = Builtin::named(name) else {
                return; // decode accepts known names only
            };
            show_builtin(ui, builtin);
        }
        SharedSurface::Embedded(grid) => match grid.to_heightfield() {
            Ok(hf) => {
                let hf = hf.with_source(format!("grid embedded in a share link ({})", grid.name));
                set_surface(ui, &grid.name, hf, Origin::Embedded);
            }
            Err(e) => {
                dom::show_load_message(&e.to_string(), true);
                return;
            }
        },
        SharedSurface::File(fingerprint) => {
            dom::show_load_message(
                &format!(
                    "This link was made on the file {} ({} bytes, FNV-1a {:016x}). Drop that \
                     file to reproduce the run; another file will be refused.",
                    fingerprint.name, fingerprint.size, fingerprint.fnv1a64
                ),
                false,
            );
            ui.waiting_for = Some(link);
            return;
        }
    }
    apply_run(ui, &link);
}

/// Checks a dropped file against the link waiting for one. `Ok(Some(link))`: this is the
/// file, apply the link after loading; `Ok(None)`: no link waits; `Err`: the wrong file.
pub(super) fn check_awaited_file(
    ui: &Ui,
    fingerprint: &FileFingerprint,
) -> Result<Option<ShareLink>, String> {
    let Some(link) = &ui.waiting_for else {
        return Ok(None);
    };
    let SharedSurface::File(expected) = &link.surface else {
        return Ok(None);
    };
    if expected.size == fingerprint.size && expected.fnv1a64 == fingerprint.fnv1a64 {
        if expected.import != fingerprint.import {
            let describe = |c: &Option<ImportChoice>| {
                c.as_ref().map_or("its own grid points".to_string(), |c| {
                    format!(
                        "the {} projection on a {}×{} grid",
                        c.projection, c.width, c.height
                    )
                })
            };
            return Err(format!(
                "{} is the right file, but the share link turned it into a grid with {} and \
                 this load used {}. Drop it again to use the link's choice.",
                fingerprint.name,
                describe(&expected.import),
                describe(&fingerprint.import)
            ));
        }
        Ok(Some(link.clone()))
    } else {
        Err(format!(
            "{} is not the file the share link expects: it needs {} ({} bytes, FNV-1a \
             {:016x}) and this one has {} bytes, FNV-1a {:016x}. Drop the right file, or \
             choose a built-in surface to leave the link.",
            fingerprint.name,
            expected.name,
            expected.size,
            expected.fnv1a64,
            fingerprint.size,
            fingerprint.fnv1a64
        ))
    }
}

/// How the file a share link waits for must be turned into a grid, if it is a mesh that is
/// not one.
pub(super) fn awaited_import(ui: &Ui) -> Option<ImportChoice> {
    match &ui.waiting_for.as_ref()?.surface {
        SharedSurface::File(f) => f.import.clone(),
        _ => None,
    }
}

/// Writes the link's run into the form and view, and re-runs it.
pub(super) fn apply_run(ui: &mut Ui, link: &ShareLink) {
    ui.waiting_for = None;
    let config = RunConfig {
        algorithm: link.algorithm,
        params: link.params.clone(),
        budget_ms: ui.app.config().budget_ms,
    };
    if let Err(e) = dom::write_config(&config) {
        dom::show_load_message(&e, true);
        return;
    }
    ui.apply_form();
    ui.app.set_config(config);
    ui.camera = link.camera;
    ui.set_toggles(link.toggles);
    ui.redraw = true;
    match ui.app.reproduce(Reproduction {
        generations: link.generations_run,
        selected: link.selected,
    }) {
        Ok(()) => {
            let what = if link.generations_run == 0 {
                "press Run to start".to_string()
            } else {
                format!(
                    "re-running {} to generation {} with seed {}",
                    link.algorithm.spec().phrase,
                    link.generations_run,
                    link.params.seed
                )
            };
            dom::show_load_message(
                &format!("Opened a share link on {}: {what}.", ui.app.surface().name),
                false,
            );
        }
        Err(e) => dom::show_load_message(&format!("The share link's run cannot start: {e}"), true),
    }
}

/// Shows built-in surface `builtin` with no run.
pub(super) fn show_builtin(ui: &mut Ui, builtin: Builtin) {
    ui.waiting_for = None;
    set_surface(
        ui,
        builtin.name,
        builtin.heightfield(),
        Origin::Builtin(builtin.name),
    );
}

/// Replaces the surface (the run and selection go with it) and resets the view.
pub(super) fn set_surface(ui: &mut Ui, name: &str, hf: Heightfield, origin: Origin) {
    ui.app.set_surface(Surface {
        name: name.to_string(),
        heightfield: Arc::new(hf),
    });
    ui.origin = origin;
    ui.hovered = None;
    ui.camera = OrbitCamera::default();
    ui.redraw = true;
    ui.surface_info();
    update_share_controls(ui);
}

/// Fills the surface menu and the Examples list. Each example is a real link (it can be copied
/// or opened in a new tab); a plain click opens it in place.
pub(super) fn fill_menus(app: &App) -> Result<(), String> {
    let document = dom::document();
    let select: HtmlSelectElement = by_id("surface")?;
    for b in BUILTINS {
        let option = document
            .create_element("option")
            .map_err(|_| "cannot create a menu entry")?;
        let _ = option.set_attribute("value", b.name);
        option.set_text_content(Some(&format!("{} ({})", b.label, b.name)));
        let _ = select.append_child(&option);
    }
    let other = document
        .create_element("option")
        .map_err(|_| "cannot create a menu entry")?;
    let _ = other.set_attribute("value", "");
    let _ = other.set_attribute("disabled", "");
    other.set_text_content(Some("a dropped file or a linked grid"));
    let _ = select.append_child(&other);
    select.set_value(&app.surface().name);

    let list: web_sys::Element = by_id("examples")?;
    for example in examples() {
        let item = document
            .create_element("li")
            .map_err(|_| "cannot create a list item")?;
        let a: web_sys::HtmlAnchorElement = document
            .create_element("a")
            .map_err(|_| "cannot create a link")?
            .unchecked_into();
        a.set_href(&format!("#{}", share::encode(&example.link)));
        a.set_text_content(Some(example.title));
        a.set_class_name("example");
        let _ = item.append_child(&a);
        let text = document
            .create_element("span")
            .map_err(|_| "cannot create a description")?;
        text.set_class_name("small");
        text.set_text_content(Some(&format!(" — {}", example.description)));
        let _ = item.append_child(&text);
        let _ = list.append_child(&item);
    }
    Ok(())
}

/// Opens example anchors in place and re-opens the hash when it changes by hand.
pub(super) fn wire(ui: &std::rc::Rc<std::cell::RefCell<Ui>>) -> Result<(), String> {
    let list: web_sys::EventTarget = by_id("examples")?;
    let u = ui.clone();
    dom::listen(&list, "click", move |e: web_sys::MouseEvent| {
        let Some(a) = e
            .target()
            .and_then(|t| t.dyn_into::<web_sys::HtmlAnchorElement>().ok())
        else {
            return;
        };
        // Let modified clicks (new tab, copy) do what the browser does.
        if e.ctrl_key() || e.meta_key() || e.shift_key() || e.button() != 0 {
            return;
        }
        e.prevent_default();
        let fragment = a.hash();
        replace_hash(fragment.trim_start_matches('#'));
        open_link(&mut u.borrow_mut(), &fragment);
    });
    let window: web_sys::EventTarget = web_sys::window().ok_or("no window")?.into();
    let u = ui.clone();
    dom::listen(&window, "hashchange", move |_: web_sys::Event| {
        let hash = web_sys::window()
            .and_then(|w| w.location().hash().ok())
            .unwrap_or_default();
        open_link(&mut u.borrow_mut(), &hash);
    });
    on_event(ui, "surface", "change", |ui| {
        let name = by_id::<HtmlSelectElement>("surface")
            .map(|s| s.value())
            .unwrap_or_default();
        if let Some(b) = Builtin::named(&name) {
            show_builtin(ui, b);
            dom::show_load_message(&format!("loaded the built-in surface {}", b.name), false);
        }
    })?;
    on_event(ui, "share", "click", share)
}
