//! The page's controls, found by id in `index.html`: reading the parameter form, writing the
//! status line and messages, and small functions for listeners and downloads.

use crate::app::algorithms::{Algorithm, Params, crossover_from_key, crossover_key};
use crate::app::state::{RunConfig, Status};
use crate::measure::ErrorMeasure;
use wasm_bindgen::JsCast;
use wasm_bindgen::prelude::*;
use web_sys::{Document, Element, HtmlElement, HtmlInputElement, HtmlSelectElement};

/// The document.
pub fn document() -> Document {
    web_sys::window()
        .and_then(|w| w.document())
        .expect("the app runs in a page with a document")
}

/// The element with `id`, cast to `T`. Fails with a message naming the missing element.
pub fn by_id<T: JsCast>(id: &str) -> Result<T, String> {
    document()
        .get_element_by_id(id)
        .ok_or_else(|| format!("index.html lacks the element #{id}"))?
        .dyn_into::<T>()
        .map_err(|_| format!("#{id} is not the expected kind of element"))
}

/// Adds a listener for `event` on `target` for the page's lifetime.
pub fn listen<E: wasm_bindgen::convert::FromWasmAbi + 'static>(
    target: &web_sys::EventTarget,
    event: &str,
    handler: impl FnMut(E) + 'static,
) {
    let closure = Closure::<dyn FnMut(E)>::new(handler);
    let _ = target.add_event_listener_with_callback(event, closure.as_ref().unchecked_ref());
    // The page keeps its listeners until it unloads.
    closure.forget();
}

/// Sets the text of element `id` (when it exists and differs, to spare layout work).
pub fn set_text(id: &str, text: &str) {
    if let Some(e) = document().get_element_by_id(id)
        && e.text_content().as_deref() != Some(text)
    {
        e.set_text_content(Some(text));
    }
}

/// Shows or hides element `id`.
pub fn set_visible(id: &str, visible: bool) {
    if let Ok(e) = by_id::<HtmlElement>(id) {
        e.set_hidden(!visible);
    }
}

/// Shows `text` in the message area next to the drop zone; `error` styles it as an error.
pub fn show_load_message(text: &str, error: bool) {
    set_text("load-message", text);
    if let Ok(e) = by_id::<Element>("load-message") {
        let _ = e.class_list().toggle_with_force("error", error);
    }
}

fn input_value(id: &str) -> Result<String, String> {
    Ok(by_id::<HtmlInputElement>(id)?.value().trim().to_string())
}

fn select_value(id: &str) -> Result<String, String> {
    Ok(by_id::<HtmlSelectElement>(id)?.value())
}

fn parse_field<T: std::str::FromStr>(id: &str, what: &str) -> Result<T, String> {
    let v = input_value(id)?;
    v.parse()
        .map_err(|_| format!("{what}: “{v}” is not a valid number"))
}

/// Fills the method menu from the catalogue (its name is the value, its label the text), with
/// the default method selected, so that a new method reaches the page with no edit here.
pub fn fill_algorithm_menu() -> Result<(), String> {
    let document = document();
    let select: HtmlSelectElement = by_id("algorithm")?;
    for algorithm in Algorithm::ALL {
        let option = document
            .create_element("option")
            .map_err(|_| "cannot create a menu entry")?;
        let _ = option.set_attribute("value", algorithm.name());
        if algorithm == Algorithm::DEFAULT {
            let _ = option.set_attribute("selected", "");
        }
        option.set_text_content(Some(algorithm.label()));
        let _ = select.append_child(&option);
    }
    select.set_value(Algorithm::DEFAULT.name());
    Ok(())
}

/// Reads the parameter form. Fails with a message naming the bad field.
pub fn read_config() -> Result<RunConfig, String> {
    let algorithm =
        Algorithm::from_name(&select_value("algorithm")?).ok_or("unknown algorithm in the menu")?;
    let crossover =
        crossover_from_key(&select_value("crossover")?).ok_or("unknown crossover in the menu")?;
    let mutation = input_value("mutation-probability")?;
    let params = Params {
        population: parse_field("population", "population")?,
        generations: parse_field("generations", "generations")?,
        crossover,
        crossover_probability: parse_field("crossover-probability", "crossover probability")?,
        mutation_probability: if mutation.is_empty() || mutation == "1/L" {
            None
        } else {
            Some(parse_field("mutation-probability", "mutation probability")?)
        },
        seed: parse_field("seed", "seed")?,
        error: ErrorMeasure::parse(&select_value("error")?)?,
    };
    params.validate()?;
    let budget_ms: f64 = parse_field("budget", "time budget")?;
    if !(1.0..=100.0).contains(&budget_ms) {
        return Err(format!(
            "time budget must be between 1 and 100 ms per frame, got {budget_ms}"
        ));
    }
    Ok(RunConfig {
        algorithm,
        params,
        budget_ms,
    })
}

/// Writes `config` into the form (the inverse of [`read_config`]).
pub fn write_config(config: &RunConfig) -> Result<(), String> {
    let p = &config.params;
    by_id::<HtmlSelectElement>("algorithm")?.set_value(config.algorithm.name());
    by_id::<HtmlSelectElement>("crossover")?.set_value(crossover_key(p.crossover));
    by_id::<HtmlInputElement>("population")?.set_value(&p.population.to_string());
    by_id::<HtmlInputElement>("generations")?.set_value(&p.generations.to_string());
    by_id::<HtmlInputElement>("crossover-probability")?
        .set_value(&p.crossover_probability.to_string());
    by_id::<HtmlInputElement>("mutation-probability")?.set_value(
        &p.mutation_probability
            .map_or("1/L".to_string(), |m| m.to_string()),
    );
    by_id::<HtmlInputElement>("seed")?.set_value(&p.seed.to_string());
    by_id::<HtmlSelectElement>("error")?.set_value(p.error.name());
    by_id::<HtmlInputElement>("budget")?.set_value(&config.budget_ms.to_string());
    Ok(())
}

/// The 2-D context of canvas `id`, its backing store sized to its CSS size times the device
/// pixel ratio and its transform set so drawing is in CSS pixels; with that CSS width and
/// height. `None` when there is no such canvas.
pub fn canvas_2d(id: &str) -> Option<(web_sys::CanvasRenderingContext2d, f64, f64)> {
    let canvas = by_id::<web_sys::HtmlCanvasElement>(id).ok()?;
    let dpr = web_sys::window().map_or(1.0, |w| w.device_pixel_ratio());
    let (cw, ch) = (canvas.client_width() as f64, canvas.client_height() as f64);
    let (pw, ph) = ((cw * dpr).round() as u32, (ch * dpr).round() as u32);
    if canvas.width() != pw || canvas.height() != ph {
        canvas.set_width(pw);
        canvas.set_height(ph);
    }
    let ctx: web_sys::CanvasRenderingContext2d = canvas.get_context("2d").ok()??.unchecked_into();
    let _ = ctx.set_transform(dpr, 0.0, 0.0, dpr, 0.0, 0.0);
    Some((ctx, cw, ch))
}

/// Is checkbox `id` ticked?
pub fn checked(id: &str) -> bool {
    by_id::<HtmlInputElement>(id).is_ok_and(|e| e.checked())
}

/// The status line's text.
pub fn status_text(s: &Status, running: bool) -> String {
    let state = if s.done {
        "done"
    } else if running {
        "running"
    } else if s.evaluations > 0 {
        "paused"
    } else {
        "ready"
    };
    format!(
        "{state} · generation {} · {} evaluations · {:.0} evaluations/s · front {} · {:.1} s",
        s.generation,
        s.evaluations,
        s.evaluations_per_second,
        s.front_size,
        s.elapsed_ms / 1000.0
    )
}

/// Offers `bytes` as a download named `name` of MIME type `mime`.
pub fn download(name: &str, mime: &str, bytes: &[u8]) -> Result<(), String> {
    let array = js_sys::Uint8Array::from(bytes);
    let parts = js_sys::Array::of1(&array);
    let options = web_sys::BlobPropertyBag::new();
    options.set_type(mime);
    let blob = web_sys::Blob::new_with_u8_array_sequence_and_options(&parts, &options)
        .map_err(|_| "the browser could not create the file")?;
    let url = web_sys::Url::create_object_url_with_blob(&blob)
        .map_err(|_| "the browser could not create a download link")?;
    let a: web_sys::HtmlAnchorElement = document()
        .create_element("a")
        .map_err(|_| "cannot create a link")?
        .unchecked_into();
    a.set_href(&url);
    a.set_download(name);
    a.click();
    // Revoking at once is safe: the click has already started the download.
    let _ = web_sys::Url::revoke_object_url(&url);
    Ok(())
}
