//! The browser bindings in a real headless browser (wasm-bindgen-test, Chromium). The app's
//! logic is tested natively in src/app/tests/.
#![cfg(target_arch = "wasm32")]

use wasm_bindgen_test::*;

wasm_bindgen_test_configure!(run_in_browser);

const GRID: &[u8] = include_bytes!("data/volcano_33x33.f32");
const SIDECAR: &[u8] = include_bytes!("data/volcano_33x33.json");

#[wasm_bindgen_test]
fn the_core_evaluates_in_the_browser_like_natively() {
    // The same kept set scored natively in tests/evaluator.rs' sense: corners only is 2 triangles.
    let value = paretomesh::web::evaluate_raw(GRID, SIDECAR, &[]).unwrap();
    let t = js_sys::Reflect::get(&value, &"T".into())
        .unwrap()
        .as_f64()
        .unwrap();
    assert_eq!(t, 2.0);
    let e = js_sys::Reflect::get(&value, &"E_sum".into())
        .unwrap()
        .as_f64()
        .unwrap();
    let native = {
        let hf = paretomesh::import::readers::raw::parse(GRID, SIDECAR, "t").unwrap();
        paretomesh::evaluator::Evaluator::new(std::sync::Arc::new(hf))
            .score(&[])
            .unwrap()
            .e_sum
    };
    assert_eq!(e, native);
    assert!(e > 0.0);
}

#[wasm_bindgen_test]
fn bad_input_is_an_error_not_a_panic() {
    // A cut-off grid: the page gets the importer's Truncated error, word for word.
    let Err(err) = paretomesh::web::evaluate_raw(&GRID[..100], SIDECAR, &[]) else {
        panic!("a cut-off grid was scored");
    };
    let native =
        paretomesh::import::readers::raw::parse(&GRID[..100], SIDECAR, "upload").unwrap_err();
    assert!(
        matches!(native, paretomesh::import::ImportError::Truncated { .. }),
        "{native:?}"
    );
    let message = js_sys::Error::from(wasm_bindgen::JsValue::from(err)).message();
    assert_eq!(String::from(message), native.to_string());
}
