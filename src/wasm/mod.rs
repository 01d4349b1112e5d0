//! The WebAssembly boundary of the playground: the only module that knows wasm-bindgen.
//!
//! One adapter per engine ([`timed`], [`sct`], [`ltl`]), each a session class that compiles a
//! text, solves it with progress and cancellation, and answers the page's queries; this module
//! holds what they share: the value conversion, the throttled progress callback, the check of
//! any document kind, and the views of generated code.
//!
//! Everything crosses as plain JS values: results are written as JSON by serde_json and parsed
//! by the page's `JSON.parse` (`None` becomes `null`); options are read by serde-wasm-bindgen.
//! Shapes are documented in `docs/playground.md`. Engines stay free of I/O and
//! of the browser; this module only adapts their results. Time is read from the page's
//! `performance` clock (web-sys): `std::time::Instant` panics on `wasm32-unknown-unknown`.

pub mod ltl;
pub mod sct;
pub mod timed;

pub use ltl::LtlSession;
pub use sct::{import_model, SctSession};
pub use timed::TimedSession;

use crate::diag::Diagnostic;
use crate::plc::{self, Target};
use serde::{de::DeserializeOwned, Deserialize, Serialize};
use wasm_bindgen::prelude::*;

#[wasm_bindgen]
extern "C" {
    /// The global `performance` of a window, a worker or Node.
    #[wasm_bindgen(thread_local_v2, js_name = performance)]
    static PERFORMANCE: web_sys::Performance;
}

/// Milliseconds on the page's monotonic clock.
pub(crate) fn now_ms() -> f64 {
    PERFORMANCE.with(web_sys::Performance::now)
}

/// `value` as a JS value: JSON text parsed by `JSON.parse`. serde-wasm-bindgen's serializer
/// built the object directly but costs more wasm per serialised type (18 KB over the views);
/// the JSON round trip gives the same values, every number here being finite and below 2^53.
pub(crate) fn to_js<T: Serialize + ?Sized>(value: &T) -> Result<JsValue, JsValue> {
    let text = serde_json::to_string(value).map_err(|e| JsValue::from_str(&e.to_string()))?;
    js_sys::JSON::parse(&text)
}

/// The options object of a call (`undefined` and `null` give the defaults).
pub(crate) fn options<T: DeserializeOwned + Default>(value: JsValue) -> Result<T, JsValue> {
    if value.is_undefined() || value.is_null() {
        return Ok(T::default());
    }
    serde_wasm_bindgen::from_value(value).map_err(|e| JsValue::from_str(&format!("bad options: {e}")))
}

/// Installs the panic hook, so that a panic reaches the console with its message.
#[wasm_bindgen(start)]
pub fn start() {
    console_error_panic_hook::set_once();
}

/// The crate version, shown in the page footer.
#[wasm_bindgen]
pub fn version() -> String {
    env!("CARGO_PKG_VERSION").to_string()
}

#[derive(Serialize)]
pub(crate) struct CheckResult<'a> {
    pub ok: bool,
    pub diagnostics: &'a [Diagnostic],
}

/// A thrown `{ ok: false, diagnostics }`.
pub(crate) fn diagnostics_error(diagnostics: &[Diagnostic]) -> JsValue {
    to_js(&CheckResult { ok: false, diagnostics }).unwrap_or_else(|e| e)
}

/// Product states the editor's check of a `.sct` text may build (the run has its own budget).
const CHECK_PRODUCT_STATES: usize = 200_000;

/// Syntax and semantic check of a document of `kind` (`tga`, `sct`, `ltl` or `tlsf`):
/// `{ ok, diagnostics }` (warnings included when `ok`). The editor calls it as you type.
#[wasm_bindgen]
pub fn check(kind: &str, source: &str) -> Result<JsValue, JsValue> {
    let (ok, diagnostics) = match kind {
        "tga" => match crate::timed::compile(source) {
            Ok((_, warnings)) => (true, warnings),
            Err(errors) => (false, errors),
        },
        // The editor checks as you type: specification products written in the file are built
        // only up to a small budget here, so a large one cannot keep the checker busy; past it
        // the text is not wrong, and Run builds the products with the run's budget.
        "sct" => {
            let mut go_on = |_: &_| true;
            let mut budget = crate::sct::model::Budget::new(CHECK_PRODUCT_STATES, &mut go_on);
            let (loaded, diagnostics, stop) = crate::sct::compile_within(source, &mut budget);
            if stop.is_some() {
                // Products are built only when nothing else is wrong: the one error is the
                // budget's, which here is a note on the product, not a mistake.
                let diagnostics = diagnostics
                    .into_iter()
                    .map(|mut d| {
                        if d.is_error() {
                            d.severity = crate::diag::Severity::Warning;
                            d.message = format!(
                                "the editor checks products up to {CHECK_PRODUCT_STATES} states and this one is larger: Run builds it"
                            );
                            d.notes.clear();
                        }
                        d
                    })
                    .collect();
                (true, diagnostics)
            } else {
                (loaded.is_some() && !diagnostics.iter().any(Diagnostic::is_error), diagnostics)
            }
        }
        "ltl" | "tlsf" => match crate::ltl::compile(source, ltl::format(kind), &[]) {
            Ok((_, warnings)) => (true, warnings),
            Err(errors) => (false, errors),
        },
        _ => return Err(JsValue::from_str(&format!("unknown document kind `{kind}` (tga, sct, ltl, tlsf)"))),
    };
    to_js(&CheckResult { ok, diagnostics: &diagnostics })
}

/// The progress callback of a solve: called with a value and the milliseconds since the start,
/// at most once per `interval_ms` (so that a fast engine does not flood the page with
/// messages); its `false` cancels the run, and an exception it throws is the run's error.
pub(crate) struct Progress {
    callback: Option<js_sys::Function>,
    interval_ms: f64,
    started: f64,
    last: f64,
    error: Option<JsValue>,
}

/// The page's default: about twenty updates a second.
pub(crate) const PROGRESS_MS: f64 = 50.0;

impl Progress {
    pub fn new(callback: Option<js_sys::Function>, interval_ms: Option<f64>) -> Progress {
        let started = now_ms();
        Progress {
            callback,
            interval_ms: interval_ms.unwrap_or(PROGRESS_MS).max(0.0),
            started,
            last: started,
            error: None,
        }
    }

    /// Reports `value()` if the interval has passed; `false` stops the run.
    pub fn report<T: Serialize>(&mut self, value: impl FnOnce() -> T) -> bool {
        if self.error.is_some() {
            return false;
        }
        let Some(f) = &self.callback else { return true };
        let now = now_ms();
        if now - self.last < self.interval_ms {
            return true;
        }
        self.last = now;
        let answer = to_js(&value()).and_then(|v| f.call2(&JsValue::NULL, &v, &JsValue::from_f64(now - self.started)));
        match answer {
            Ok(answer) => answer.as_bool() != Some(false),
            Err(e) => {
                self.error = Some(e);
                false
            }
        }
    }

    /// Milliseconds since the start.
    pub fn elapsed(&self) -> f64 {
        now_ms() - self.started
    }

    /// The callback's exception, if it threw.
    pub fn finish(self) -> Result<(), JsValue> {
        self.error.map_or(Ok(()), Err)
    }
}

/// A code target of the page's menu.
#[derive(Serialize)]
struct TargetInfo {
    /// `program` (the timed engine's intermediate language) or a [`Target`] name.
    id: &'static str,
    label: &'static str,
    extension: &'static str,
    /// Whether the target writes several files (TwinCAT).
    multi_file: bool,
}

/// The code targets: the intermediate program (timed games only) first, then every PLC back
/// end, which every engine generates.
#[wasm_bindgen]
pub fn targets() -> Result<JsValue, JsValue> {
    let mut list = vec![TargetInfo {
        id: "program",
        label: "Intermediate program (thesis notation)",
        extension: "txt",
        multi_file: false,
    }];
    for target in Target::ALL {
        list.push(TargetInfo {
            id: target.name(),
            label: target.label(),
            extension: target.extension(),
            multi_file: target.multi_file(),
        });
    }
    to_js(&list)
}

/// A PLC target by name.
pub(crate) fn plc_target(name: &str) -> Result<Target, JsValue> {
    name.parse().map_err(|e: plc::UnknownTarget| JsValue::from_str(&e.to_string()))
}

/// Generated code as the page shows it.
#[derive(Serialize)]
pub(crate) struct GeneratedCode {
    pub target: String,
    pub extension: &'static str,
    /// The files, each `{ name, text }` (TwinCAT: three; the others one). The page shows them
    /// as one text, each after a line `==> NAME <==` when there are several.
    pub files: Vec<FileView>,
    /// The I/O table, `{ address, type, symbol, direction, meaning }[]` (empty for `program`).
    pub io: Vec<IoRowView>,
    /// The I/O table as CSV, and (timed games) as a Siemens SDF symbol table; else empty.
    pub io_csv: String,
    pub io_sdf: String,
    /// The I/O as the CODESYS I/O mapping list (`plc::codesys_mapping_csv`); empty for `program`.
    pub io_codesys: String,
    /// At a declared scan time at which a timed specification is implementable: the real-time
    /// check of the code (`plc::lower::timed::realtime::check`); when it failed, `files` is empty.
    pub realtime: Option<timed::RealtimeView>,
}

#[derive(Serialize)]
pub(crate) struct FileView {
    pub name: String,
    pub text: String,
}

#[derive(Serialize)]
pub(crate) struct IoRowView {
    pub address: String,
    #[serde(rename = "type")]
    pub data_type: &'static str,
    pub symbol: String,
    pub direction: &'static str,
    pub meaning: String,
}

/// Options of the code generation of a structured unit (supervisory control, LTL).
#[derive(Deserialize, Default)]
#[serde(rename_all = "camelCase", default)]
pub(crate) struct UnitCodeOptions {
    /// PLCopen's creation time, seconds since 1970 (from the page's clock).
    pub created_unix: Option<f64>,
}

/// A structured unit (the runtime framework, an LTL function block) printed for `target`,
/// with its signal table.
pub(crate) fn unit_code(
    unit: &plc::model::unit::Unit,
    target: &str,
    options: &plc::Options,
) -> Result<GeneratedCode, JsValue> {
    let t = plc_target(target)?;
    let files = plc::render_unit_files(unit, t, options).map_err(|e| JsValue::from_str(&e))?;
    let io = plc::signal_rows(unit)
        .into_iter()
        .map(|r| IoRowView {
            address: r.address,
            data_type: r.data_type,
            symbol: r.symbol,
            direction: r.direction,
            meaning: r.events,
        })
        .collect();
    Ok(GeneratedCode {
        target: target.to_string(),
        extension: t.extension(),
        files: files.into_iter().map(|f| FileView { name: f.name, text: f.text }).collect(),
        io,
        io_csv: plc::signal_table_csv(unit),
        io_sdf: String::new(),
        io_codesys: plc::codesys_mapping_csv(unit),
        realtime: None,
    })
}
