//! The wasm boundary (`src/wasm/`), run with wasm-bindgen-test in Node:
//! `cargo test --target wasm32-unknown-unknown --test wasm_api` (runner in `.cargo/config.toml`).
#![cfg(target_arch = "wasm32")]

use js_sys::{Array, Function, Reflect};
use plcsynth::wasm::{check, import_model, targets, version, LtlSession, SctSession, TimedSession as Session};
use wasm_bindgen::{JsCast, JsValue};
use wasm_bindgen_test::*;

const LAMP: &str = include_str!("../examples/timed/lamp.tga");
const LAMP_NAIVE: &str = include_str!("../examples/timed/lamp_naive.tga");
const RT4: &str = include_str!("../examples/timed/round_table_4.tga");
const LAMP_SCAN: &str = include_str!("../examples/timed/lamp_scan.tga");
const HARDWARE_XYZ: &str = include_str!("../examples/timed/hardware_xyz.tga");
const GRIPPER_GUARD: &str = include_str!("../examples/timed/gripper_guard.tga");
const WATCHDOG: &str = include_str!("fixtures/timed/watchdog.tga");

fn get(v: &JsValue, key: &str) -> JsValue {
    Reflect::get(v, &JsValue::from_str(key)).unwrap()
}

fn num(v: &JsValue, key: &str) -> f64 {
    get(v, key).as_f64().unwrap_or_else(|| panic!("{key} is not a number"))
}

fn string(v: &JsValue, key: &str) -> String {
    get(v, key).as_string().unwrap_or_else(|| panic!("{key} is not a string"))
}

fn array(v: &JsValue) -> Array {
    v.clone().dyn_into::<Array>().expect("an array")
}

fn solved(src: &str) -> (Session, JsValue) {
    let mut s = Session::new(src).map_err(|_| "compile failed").unwrap();
    let summary = s.solve(JsValue::UNDEFINED, None).unwrap();
    (s, summary)
}

#[wasm_bindgen_test]
fn version_is_the_crate_version() {
    assert_eq!(version(), env!("CARGO_PKG_VERSION"));
}

#[wasm_bindgen_test]
fn check_reports_located_syntax_errors() {
    let result = check("tga", "plant {\n  automaton a {\n    nodes x y;\n  }\n}\n").unwrap();
    let diags = array(&get(&result, "diagnostics"));
    assert!(diags.length() >= 1);
    let d = diags.get(0);
    assert_eq!(string(&d, "severity"), "error");
    assert_eq!(num(&d, "line"), 3.0);
    assert!(num(&get(&d, "span"), "end") >= num(&get(&d, "span"), "start"));
    assert!(!string(&d, "message").is_empty());
    assert_eq!(array(&get(&check("tga", LAMP).unwrap(), "diagnostics")).length(), 0);
    assert!(check("xyz", LAMP).is_err(), "an unknown kind is refused");
}

#[wasm_bindgen_test]
fn check_separates_ok_from_errors() {
    let ok = check("tga", LAMP).unwrap();
    assert_eq!(get(&ok, "ok").as_bool(), Some(true));
    let bad = check("tga", "plant { automaton a { nodes x; x -> y ?m; } }").unwrap();
    assert_eq!(get(&bad, "ok").as_bool(), Some(false));
    let diags = array(&get(&bad, "diagnostics"));
    assert!(diags.length() >= 1, "an unknown location is an error");
}

#[wasm_bindgen_test]
fn session_constructor_throws_the_diagnostics() {
    let err = Session::new("plant {").err().expect("a syntax error must not compile");
    assert_eq!(get(&err, "ok").as_bool(), Some(false));
    assert!(array(&get(&err, "diagnostics")).length() >= 1);
}

#[wasm_bindgen_test]
fn automata_have_locations_and_typed_edges() {
    let s = Session::new(LAMP).map_err(|_| "compile").unwrap();
    let automata = array(&s.automata().unwrap());
    let names: Vec<String> = automata.iter().map(|a| string(&a, "name")).collect();
    assert!(names.contains(&"lamp".to_string()) && names.contains(&"button".to_string()), "{names:?}");
    let button = automata.iter().find(|a| string(a, "name") == "button").unwrap();
    let locations = array(&get(&button, "locations"));
    assert_eq!(locations.length(), 4);
    assert!(locations.iter().any(|l| string(&l, "invariant").contains("c in")));
    let sigils: Vec<String> = automata
        .iter()
        .flat_map(|a| array(&get(&a, "edges")).iter().map(|e| string(&e, "sigil")).collect::<Vec<_>>())
        .collect();
    for sigil in ["?", "!", "$"] {
        assert!(sigils.iter().any(|x| x == sigil), "no {sigil} edge in {sigils:?}");
    }
    // Each comes with its drawing: the edges classed by sigil, the invariant in its location.
    let dot = string(&button, "dot");
    assert!(dot.starts_with("digraph"), "{dot}");
    assert!(dot.contains("class = \"edge-reaction\", style = dashed"), "{dot}");
    assert!(dot.contains("c in [0,1)"), "{dot}");
    assert!(string(&automata.get(0), "dot").contains("edge-request"));
}

#[wasm_bindgen_test]
fn solve_lamp_is_realizable_with_a_state_space() {
    let (s, summary) = solved(LAMP);
    assert_eq!(string(&summary, "verdict"), "realizable");
    let stats = get(&summary, "stats");
    let visited = num(&stats, "visited");
    assert!(visited > 0.0 && num(&stats, "winning") > 0.0 && num(&stats, "winning") <= visited);
    assert!(get(&summary, "explanation_depth").is_null());
    assert!(s.explanation().unwrap().is_null());
    assert!(s.explanation_text().unwrap().is_none());

    let space = s.space(1000).unwrap();
    assert_eq!(num(&space, "total_states"), visited);
    assert_eq!(get(&space, "truncated").as_bool(), Some(false));
    let states = array(&get(&space, "states"));
    assert_eq!(states.length() as f64, visited);
    let first = states.get(0);
    assert_eq!(num(&first, "id"), num(&space, "initial"));
    assert!(array(&get(&first, "locations")).length() >= 2);
    assert!(array(&get(&space, "edges")).length() > 0);

    let small = s.space(3).unwrap();
    assert_eq!(array(&get(&small, "states")).length(), 3);
    assert_eq!(get(&small, "truncated").as_bool(), Some(true));

    let dump = s.dump().unwrap();
    assert!(dump.starts_with("s0"), "{dump}");
    assert!(dump.contains("winning"));
}

#[wasm_bindgen_test]
fn unrealizable_lamp_has_an_explanation() {
    let (s, summary) = solved(LAMP_NAIVE);
    assert_eq!(string(&summary, "verdict"), "unrealizable");
    assert!(num(&summary, "explanation_depth") >= 0.0);
    let tree = s.explanation().unwrap();
    assert!(!get(&get(&tree, "root"), "outcome").is_undefined());
    let text = s.explanation_text().unwrap().expect("an explanation");
    assert!(text.contains('✗'), "{text}");
    let initial = s.state(0).unwrap();
    assert_eq!(get(&initial, "winning").as_bool(), Some(false));
    assert!(get(&initial, "reason").as_string().is_some());
}

#[wasm_bindgen_test]
fn progress_is_reported_and_false_cancels() {
    let mut s = Session::new(RT4).map_err(|_| "compile").unwrap();
    let calls = Array::new();
    let log = Function::new_with_args("stats", "this.push(stats.visited); return this.length < 2;").bind0(&calls);
    let options = js_sys::JSON::parse(r#"{"progressInterval": 10, "progressMs": 0}"#).unwrap();
    let summary = s.solve(options, Some(log)).unwrap();
    assert_eq!(string(&summary, "verdict"), "cancelled");
    assert_eq!(calls.length(), 2, "the run stops at the first false");
    assert!(calls.get(0).as_f64().unwrap() > 0.0);
}

#[wasm_bindgen_test]
fn budget_exceeded_keeps_statistics() {
    let mut s = Session::new(RT4).map_err(|_| "compile").unwrap();
    let options = js_sys::JSON::parse(r#"{"maxStates": 50}"#).unwrap();
    let summary = s.solve(options, None).unwrap();
    assert_eq!(string(&summary, "verdict"), "budget_exceeded");
    assert!(num(&get(&summary, "stats"), "visited") >= 50.0);
    let stop = get(&summary, "stop");
    assert_eq!(string(&stop, "stop"), "budget");
    assert_eq!(string(&stop, "resource"), "states");
    assert_eq!(string(&stop, "message"), "the search stored more than 50 states");
    assert!(get(&summary, "blame").is_null());
}

#[wasm_bindgen_test]
fn memory_and_work_budgets_are_options() {
    let mut s = Session::new(RT4).map_err(|_| "compile").unwrap();
    // The reference explores the whole game: enough work and memory to hit small budgets.
    let options = js_sys::JSON::parse(r#"{"maxWork": 10000, "exhaustive": true}"#).unwrap();
    let summary = s.solve(options, None).unwrap();
    assert_eq!(string(&summary, "verdict"), "budget_exceeded");
    assert_eq!(string(&get(&summary, "stop"), "resource"), "work");
    assert!(num(&get(&summary, "stats"), "work") > 10000.0);
    let options = js_sys::JSON::parse(r#"{"maxMemoryMib": 1, "exhaustive": true}"#).unwrap();
    let summary = s.solve(options, None).unwrap();
    assert_eq!(string(&get(&summary, "stop"), "resource"), "memory");
    let summary = s.solve(JsValue::UNDEFINED, None).unwrap();
    assert_eq!(string(&summary, "verdict"), "realizable");
    assert!(get(&summary, "stop").is_null());
}

#[wasm_bindgen_test]
fn a_throwing_progress_callback_surfaces_as_an_error() {
    let mut s = Session::new(LAMP).map_err(|_| "compile").unwrap();
    let boom = Function::new_with_args("stats", "throw new Error('boom')");
    let options = js_sys::JSON::parse(r#"{"progressInterval": 1, "progressMs": 0}"#).unwrap();
    assert!(s.solve(options, Some(boom)).is_err());
}

#[wasm_bindgen_test]
fn queries_need_a_solve_first() {
    let s = Session::new(LAMP).map_err(|_| "compile").unwrap();
    assert!(s.space(10).is_err());
    assert!(s.dump().is_err());
}

#[wasm_bindgen_test]
fn state_search_and_neighbourhood() {
    let (s, summary) = solved(RT4);
    let total = num(&get(&summary, "stats"), "visited");
    let all = s.states("", "all", 5).unwrap();
    assert_eq!(num(&all, "total"), total);
    assert_eq!(array(&get(&all, "rows")).length(), 5);
    let first = array(&get(&all, "rows")).get(0);
    assert_eq!(get(&first, "initial").as_bool(), Some(true));
    assert!(string(&first, "text").contains("table."), "rows are described without a query too");
    let winning = s.states("", "winning", 0).unwrap();
    let removed = s.states("", "removed", 0).unwrap();
    assert_eq!(num(&winning, "total") + num(&removed, "total"), total);
    let hits = s.states("pos_0.p3", "all", 1000).unwrap();
    assert!(num(&hits, "total") > 0.0 && num(&hits, "total") < total);
    for row in array(&get(&hits, "rows")).iter() {
        assert!(string(&row, "text").contains("pos_0.p3"));
    }

    let hood = s.neighbourhood(0, 1, 100).unwrap();
    let states = array(&get(&hood, "states"));
    assert!(states.length() >= 2);
    assert_eq!(num(&states.get(0), "id"), 0.0);
    let ids: Vec<f64> = states.iter().map(|x| num(&x, "id")).collect();
    for e in array(&get(&hood, "edges")).iter() {
        assert!(ids.contains(&num(&e, "from")));
    }
    let two = s.neighbourhood(0, 2, 100_000).unwrap();
    assert!(array(&get(&two, "states")).length() > states.length());
    assert!(s.neighbourhood(u32::MAX - 1, 1, 10).is_err());
}

#[wasm_bindgen_test]
fn targets_list_the_program_and_every_plc_back_end() {
    let list = array(&targets().unwrap());
    let ids: Vec<String> = list.iter().map(|t| string(&t, "id")).collect();
    assert_eq!(ids, ["program", "st", "twincat", "codesys", "scl", "scl-1500", "il", "stl", "plcopen", "abb"]);
    let exts: Vec<String> = list.iter().map(|t| string(&t, "extension")).collect();
    assert_eq!(exts, ["txt", "st", "TcPOU", "st", "scl", "scl", "il", "awl", "xml", "xml"]);
}

#[wasm_bindgen_test]
fn code_for_every_target_of_a_realizable_spec() {
    let (s, _) = solved(LAMP);
    let program = s.program().unwrap().expect("a controller");
    assert!(program.contains("DO (turn_on)"), "{program}");
    for (target, marker) in [
        ("program", "DO (turn_on)"),
        ("st", "FUNCTION_BLOCK"),
        ("twincat", "<TcPlcObject"),
        ("scl", "FUNCTION_BLOCK"),
        ("scl-1500", "S7_Optimized_Access"),
        ("codesys", "FUNCTION_BLOCK"),
        ("il", "turn_on"),
        ("stl", "turn_on"),
        ("plcopen", "<project"),
        ("abb", "interval=\"PT0.010S\""),
    ] {
        let code = s.code(target, "lamp", Some(1_700_000_000.0)).unwrap();
        assert_eq!(string(&code, "target"), target);
        let files = array(&get(&code, "files"));
        let text = string(&files.get(0), "text");
        assert!(text.contains(marker), "{target}: no {marker} in\n{text}");
        assert_eq!(files.length(), if target == "twincat" { 3 } else { 1 }, "{target}");
        let io = array(&get(&code, "io"));
        assert_eq!(io.length(), if target == "program" { 0 } else { 2 }, "{target}");
    }
    let code = s.code("plcopen", "lamp", Some(1_700_000_000.0)).unwrap();
    let files = array(&get(&code, "files"));
    assert_eq!(string(&files.get(0), "name"), "lamp.xml");
    assert!(string(&files.get(0), "text").contains("creationDateTime=\"2023-11-14T22:13:20\""));
    let row = array(&get(&code, "io")).get(0);
    assert_eq!(
        (string(&row, "address"), string(&row, "symbol"), string(&row, "direction")),
        ("%IX124.0".to_string(), "press".to_string(), "input".to_string())
    );
    assert!(string(&code, "io_csv").starts_with("address,type,symbol,direction,meaning"));
    assert!(string(&code, "io_sdf").starts_with("\"press\",\"I 124.0\""));
    assert!(string(&code, "io_codesys").starts_with("Variable;Address;Type;Direction;Description\r\nGVL_IO.press;"));
    assert!(s.code("cobol", "lamp", None).is_err());
}

#[wasm_bindgen_test]
fn a_constant_beyond_the_target_throws_located_diagnostics() {
    // 10 000 s is beyond S5TIME (2h46m30s) but within IEC TIME.
    let src = "timeunit 10s;\nplant { automaton A { clocks x; nodes a, b;\n  a -> b ?go { x in [1000,inf) } reset { x }; b -> a ?back; } }\nplans { plan { waitfor go; waitfor back; } }\n";
    let (s, _) = solved(src);
    let files = array(&get(&s.code("st", "a", None).unwrap(), "files"));
    assert!(string(&files.get(0), "text").contains("T#10000000MS"));
    let thrown = s.code("stl", "a", None).expect_err("S5TIME cannot hold 10 000 s");
    assert_eq!(get(&thrown, "ok"), JsValue::FALSE);
    let diagnostics = array(&get(&thrown, "diagnostics"));
    assert_eq!(diagnostics.length(), 1);
    let d = diagnostics.get(0);
    assert_eq!((num(&d, "line"), num(&d, "column")), (3.0, 22.0));
    assert!(string(&d, "message").contains("exceeds S5TIME"), "{:?}", string(&d, "message"));
}

#[wasm_bindgen_test]
fn code_at_a_declared_scan_time_is_run_against_the_plant_first() {
    // Without a scan time there is no check.
    let (s, _) = solved(LAMP);
    assert!(get(&s.code("st", "lamp", None).unwrap(), "realtime").is_null());
    // lamp_scan holds at its 10 ms.
    let (s, _) = solved(LAMP_SCAN);
    let code = s.code("stl", "lamp_scan", None).unwrap();
    let realtime = get(&code, "realtime");
    assert_eq!(num(&realtime, "scan_ms"), 10.0);
    assert_eq!(num(&realtime, "runs"), 20.0);
    assert!(get(&realtime, "failure").is_null());
    assert_eq!(array(&get(&code, "files")).length(), 1);
    // The watchdog is implementable at 250 ms, but its scan strategy needs a timer: its code
    // follows the zero-time strategy and fails a run there: no files.
    let (s, summary) = solved(&format!("scan 250 ms;\n{WATCHDOG}"));
    assert_eq!(string(&get(&summary, "scan"), "verdict"), "realizable");
    assert!(string(&get(&summary, "scan"), "code_from").contains("zero-time strategy"));
    for target in ["st", "program"] {
        let code = s.code(target, "watchdog", None).unwrap();
        let realtime = get(&code, "realtime");
        assert!(string(&realtime, "failure").contains("RequestRefused"), "{target}");
        assert!(array(&get(&realtime, "trace")).length() > 2);
        assert_eq!(array(&get(&code, "files")).length(), 0, "{target}");
    }
    // gripper_guard's (a state guard) follows its scan strategy and holds at 100 ms; at 500 ms a
    // guard read FALSE costs a plan its bound, and the page is told why.
    let (s, _) = solved(&format!("scan 500 ms;\n{GRIPPER_GUARD}"));
    let realtime = get(&s.code("st", "gripper_guard", None).unwrap(), "realtime");
    assert!(string(&realtime, "why").contains("a state guard holds whenever the code checks it"));
    let (s, summary) = solved(&format!("scan 100 ms;\n{GRIPPER_GUARD}"));
    assert!(string(&get(&summary, "scan"), "code_from").starts_with("the scan strategy"));
    assert!(get(&get(&s.code("st", "gripper_guard", None).unwrap(), "realtime"), "failure").is_null());
    // hardware_xyz's code follows its scan strategy and holds at 495 ms.
    let (s, summary) = solved(&format!("scan 495 ms;\n{HARDWARE_XYZ}"));
    assert!(string(&get(&summary, "scan"), "code_from").starts_with("the scan strategy"));
    let code = s.code("st", "hardware_xyz", None).unwrap();
    assert!(get(&get(&code, "realtime"), "failure").is_null());
    assert_eq!(array(&get(&code, "files")).length(), 1);
}

#[wasm_bindgen_test]
fn no_code_without_a_controller() {
    let (s, _) = solved(LAMP_NAIVE);
    assert!(s.program().unwrap().is_none());
    assert!(s.code("st", "lamp_naive", None).unwrap().is_null());
    let unsolved = Session::new(LAMP).map_err(|_| "compile").unwrap();
    assert!(unsolved.code("st", "lamp", None).is_err());
}

#[wasm_bindgen_test]
fn strategy_requests_stay_among_winning_states() {
    let (s, summary) = solved(LAMP);
    let choices = array(&s.strategy().unwrap());
    assert!(choices.length() > 0);
    let first = choices.get(0);
    let space = s.space(10_000).unwrap();
    assert_eq!(num(&first, "state"), num(&space, "initial"));
    let states = array(&get(&space, "states"));
    let winning = |id: f64| {
        states.iter().find(|x| num(x, "id") == id).map(|x| get(&x, "winning").as_bool() == Some(true)).unwrap()
    };
    let mut requests = 0;
    for c in choices.iter() {
        assert!(winning(num(&c, "state")));
        match string(&c, "choice").as_str() {
            "request" => {
                requests += 1;
                assert!(winning(num(&c, "to")));
                assert!(string(&c, "label").starts_with('?'), "{}", string(&c, "label"));
            }
            "wait" => assert!(get(&c, "to").is_null()),
            other => panic!("choice {other}"),
        }
    }
    assert!(requests >= 2, "the lamp controller turns the lamp on and off");
    assert!(num(&get(&summary, "stats"), "winning") >= choices.length() as f64);
    let (naive, _) = solved(LAMP_NAIVE);
    assert!(naive.strategy().unwrap().is_null());
}

const TANK_PREEMPTION: &str = include_str!("../examples/sct/tank_preemption.sct");
const ENFORCEMENT_CONFLICT: &str = include_str!("../examples/sct/enforcement_conflict.sct");
const ARBITER: &str = include_str!("../examples/ltl/arbiter.ltl");
const ARBITER_SAME_SCAN: &str = include_str!("../examples/ltl/arbiter_same_scan.ltl");
const DELAY_LINE: &str = include_str!("../examples/ltl/delay_line.tlsf");

#[wasm_bindgen_test]
fn check_reads_every_document_kind() {
    for (kind, source) in [("sct", TANK_PREEMPTION), ("ltl", ARBITER), ("tlsf", DELAY_LINE)] {
        let result = check(kind, source).unwrap();
        assert_eq!(get(&result, "ok").as_bool(), Some(true), "{kind}");
    }
    let bad = check("sct", "event open : controllable;\nplant P { alphabet open, nope; state A { } }").unwrap();
    assert_eq!(get(&bad, "ok").as_bool(), Some(false));
    let d = array(&get(&bad, "diagnostics")).get(0);
    assert_eq!((num(&d, "line"), string(&d, "severity")), (2.0, "error".to_string()));
    let bad = check("ltl", "INPUT a\nOUTPUT b\nALWAYS (a -> \n").unwrap();
    assert_eq!(get(&bad, "ok").as_bool(), Some(false));
    let bad = check("tlsf", "INFO { TITLE: \"x\" }\nMAIN { INPUTS { a; } OUTPUTS { b; } GUARANTEES { G (a <-> ; } }")
        .unwrap();
    assert_eq!(get(&bad, "ok").as_bool(), Some(false));
}

#[wasm_bindgen_test]
fn sct_session_draws_synthesises_and_generates_the_framework() {
    assert!(SctSession::new("plant {", JsValue::UNDEFINED).is_err());
    let mut s = SctSession::new(TANK_PREEMPTION, JsValue::UNDEFINED).map_err(|_| "compile").unwrap();
    let models = array(&s.models().unwrap());
    assert!(models.length() >= 2);
    assert!(string(&models.get(0), "dot").starts_with("digraph"));
    assert!(s.supervisors().is_err(), "no supervisors before solve");
    let calls = Array::new();
    let log = Function::new_with_args("p, ms", "this.push(p.built); return true;").bind0(&calls);
    let summary = s.solve(js_sys::JSON::parse(r#"{"progressMs": 0}"#).unwrap(), Some(log)).unwrap();
    assert!(get(&summary, "stop").is_null());
    let sups = array(&get(&summary, "supervisors"));
    assert_eq!(sups.length(), 1);
    let sup = sups.get(0);
    assert_eq!(string(&sup, "name"), "Safety.NoOverflow");
    assert_eq!(string(&sup, "module"), "Safety");
    assert_eq!(get(&sup, "realizable").as_bool(), Some(true));
    assert!(array(&get(&sup, "enforced_events")).length() >= 1, "preemption enforces closing the inlet");
    let drawn = array(&s.supervisors().unwrap());
    assert!(string(&drawn.get(0), "dot").contains("⇒"), "the enforced event is marked");
    for target in ["st", "twincat", "codesys", "scl", "scl-1500", "stl", "plcopen", "abb"] {
        let code = s.code(target, "", "", JsValue::UNDEFINED).unwrap();
        let files = array(&get(&code, "files"));
        assert!(files.length() >= 1, "{target}");
        assert!(!string(&files.get(0), "text").is_empty(), "{target}");
        assert!(array(&get(&code, "io")).length() >= 1, "{target}: the signal table");
    }
    assert!(s.code("no-such-target", "", "", JsValue::UNDEFINED).is_err());
    // A budget too small for the products stops the run, reported and not thrown.
    let summary = s.solve(js_sys::JSON::parse(r#"{"maxStates": 1}"#).unwrap(), None).unwrap();
    assert_eq!(string(&get(&summary, "stop"), "stop"), "budget");
    assert_eq!(string(&get(&summary, "stop"), "resource"), "states");
    assert!(s.code("st", "", "", JsValue::UNDEFINED).unwrap().is_null(), "no framework for an incomplete run");
}

#[wasm_bindgen_test]
fn sct_conflicts_between_supervisors_are_located_warnings() {
    // Without its product line the two requirements are synthesised apart, and conflict.
    let apart: String =
        ENFORCEMENT_CONFLICT.lines().filter(|l| !l.starts_with("spec Safety =")).collect::<Vec<_>>().join("\n");
    let mut s = SctSession::new(&apart, JsValue::UNDEFINED).map_err(|_| "compile").unwrap();
    let summary = s.solve(JsValue::UNDEFINED, None).unwrap();
    assert_eq!(array(&get(&summary, "supervisors")).length(), 2);
    let diags = array(&get(&summary, "diagnostics"));
    let warning = (0..diags.length()).map(|i| diags.get(i)).find(|d| string(d, "severity") == "warning");
    let warning = warning.expect("the 6.4.2 warning");
    assert!(num(&warning, "line") > 1.0);
    // Composing them (5.8.5) gives one supervisor and no warning.
    let summary = s.solve(js_sys::JSON::parse(r#"{"compose": true}"#).unwrap(), None).unwrap();
    let sups = array(&get(&summary, "supervisors"));
    assert_eq!((sups.length(), string(&sups.get(0), "name")), (1, "Composed".to_string()));
    assert_eq!(array(&get(&summary, "diagnostics")).length(), 0);
    assert!(s.code("st", "", "", JsValue::UNDEFINED).unwrap().is_object(), "the framework of the composed supervisor");
}

#[wasm_bindgen_test]
fn ltl_session_decides_draws_and_generates_code() {
    assert!(LtlSession::new("ALWAYS (", "ltl").is_err());
    let mut s = LtlSession::new(ARBITER, "ltl").map_err(|_| "compile").unwrap();
    assert!(s.code("st", "", JsValue::UNDEFINED).is_err(), "code needs a solve first");
    let summary = s.solve(JsValue::UNDEFINED, None).unwrap();
    assert_eq!(string(&summary, "verdict"), "realizable");
    assert!(string(&summary, "machine_dot").starts_with("digraph"));
    assert!(string(&summary, "machine_text").contains(" / "));
    assert!(get(&summary, "counter_tree").is_null());
    for target in ["st", "twincat", "stl", "plcopen", "abb"] {
        let code = s.code(target, "FB_Arbiter", JsValue::UNDEFINED).unwrap();
        let text = string(&array(&get(&code, "files")).get(0), "text");
        assert!(text.contains("FB_Arbiter"), "{target}: {text}");
    }
    let mut s = LtlSession::new(DELAY_LINE, "tlsf").map_err(|_| "compile").unwrap();
    assert_eq!(string(&s.solve(JsValue::UNDEFINED, None).unwrap(), "verdict"), "realizable");
    assert!(get(&summary, "stop").is_null());
}

/// A stopped LTL run reports as the other engines' sessions do: the verdict word of the stop
/// and the shared `stop` object, not an exception.
#[wasm_bindgen_test]
fn ltl_stops_are_reported_as_the_other_engines_report_them() {
    let mut s = LtlSession::new(ARBITER, "ltl").map_err(|_| "compile").unwrap();
    let summary = s.solve(js_sys::JSON::parse(r#"{"maxWork": 10}"#).unwrap(), None).unwrap();
    assert_eq!(string(&summary, "verdict"), "budget_exceeded");
    assert_eq!(string(&get(&summary, "stop"), "stop"), "budget");
    assert_eq!(string(&get(&summary, "stop"), "resource"), "work");
    assert!(string(&get(&summary, "stop"), "message").contains("units of work"));
    assert!(get(&summary, "machine_dot").is_null());
    // The mutex spends enough work (about 480 000 units) to call the progress callback.
    let mut s = LtlSession::new(include_str!("../examples/ltl/mutex.tlsf"), "tlsf").map_err(|_| "compile").unwrap();
    let cancel = js_sys::Function::new_no_args("return false");
    let summary = s.solve(js_sys::JSON::parse(r#"{"progressMs": 0}"#).unwrap(), Some(cancel)).unwrap();
    assert_eq!(string(&summary, "verdict"), "cancelled");
    assert_eq!(string(&get(&summary, "stop"), "stop"), "cancelled");
}

#[wasm_bindgen_test]
fn ltl_progress_carries_positions_and_diagram_nodes() {
    // The mutex spends enough work (about 480 000 units) to be reported (every 65 536 units);
    // `nodes` is the bdd solver's (tests/ltl_symbolic.rs), 0 for the explicit one.
    let mut s = LtlSession::new(include_str!("../examples/ltl/mutex.tlsf"), "tlsf").map_err(|_| "compile").unwrap();
    let calls = Array::new();
    let log = Function::new_with_args("p, ms", "this.push(p); return true;").bind0(&calls);
    let summary = s.solve(js_sys::JSON::parse(r#"{"progressMs": 0}"#).unwrap(), Some(log)).unwrap();
    assert_eq!(string(&summary, "verdict"), "realizable");
    assert!(calls.length() > 0, "no progress reported");
    for key in ["k", "positions", "nodes", "work"] {
        assert!(calls.iter().all(|p| get(&p, key).as_f64().is_some()), "{key}");
    }
    assert!(calls.iter().any(|p| get(&p, "positions").as_f64() > Some(0.0)));
    assert!(calls.iter().all(|p| get(&p, "nodes").as_f64() == Some(0.0)));
}

/// The GR(1) game in the page: SYNTCOMP's simple arbiter with 12 clients (24 signals, which
/// the bounded games do not decide) is realizable; its controller table is past the budget
/// given, so the controller comes as a circuit, shown as text, and its function block is the
/// code.
#[wasm_bindgen_test]
fn ltl_gr1_decides_an_arbiter_of_24_signals() {
    let source =
        include_str!(concat!(env!("CARGO_MANIFEST_DIR"), "/../shared/ltl/tlsf/simple_arbiter/simple_arbiter.tlsf"))
            .replace("n = 2;", "n = 12;");
    let mut s = LtlSession::new(&source, "tlsf").map_err(|_| "compile").unwrap();
    let options = js_sys::JSON::parse(r#"{"solver": "gr1", "maxStates": 2000}"#).unwrap();
    let summary = s.solve(options, None).unwrap();
    assert_eq!(string(&summary, "verdict"), "realizable");
    assert_eq!(string(&summary, "solver"), "gr1");
    assert!(string(&summary, "summary").contains("GR(1) game"), "{}", string(&summary, "summary"));
    assert!(string(&summary, "summary").contains("circuit of 12 latches"), "{}", string(&summary, "summary"));
    assert!(get(&summary, "machine_dot").is_null());
    assert!(string(&summary, "circuit_text").contains("g_11 = open_12"), "{}", string(&summary, "circuit_text"));
    let code = s.code("st", "", JsValue::UNDEFINED).unwrap();
    let text = string(&array(&get(&code, "files")).get(0), "text");
    assert!(text.contains("CASE goal OF") && text.contains("open_12 := (open_12 OR r_11) AND NOT g_11;"), "{text}");
}

#[wasm_bindgen_test]
fn ltl_unrealizable_has_a_counter_strategy_and_suggestions() {
    let mut s = LtlSession::new(ARBITER_SAME_SCAN, "ltl").map_err(|_| "compile").unwrap();
    let summary = s.solve(js_sys::JSON::parse(r#"{"suggest": true}"#).unwrap(), None).unwrap();
    assert_eq!(string(&summary, "verdict"), "unrealizable");
    assert!(string(&summary, "counter_tree").contains("s0"));
    let found = array(&get(&get(&summary, "suggestions"), "found"));
    assert!(found.length() >= 1, "an assumption makes it realizable");
    let first = array(&get(&found.get(0), "assumptions"));
    assert!(!first.get(0).as_string().unwrap().is_empty());
    assert!(s.code("st", "", JsValue::UNDEFINED).unwrap().is_null(), "no controller, no code");
    // Adding the first suggestion makes the specification realizable.
    let added = format!("{ARBITER_SAME_SCAN}\nASSUME {}\n", first.get(0).as_string().unwrap());
    let mut s = LtlSession::new(&added, "ltl").map_err(|_| "compile").unwrap();
    assert_eq!(string(&s.solve(JsValue::UNDEFINED, None).unwrap(), "verdict"), "realizable");
}

#[wasm_bindgen_test]
fn sct_stepper_and_runtime_cycles() {
    let mut s = SctSession::new(TANK_PREEMPTION, JsValue::UNDEFINED).map_err(|_| "compile").unwrap();
    assert!(s.step(JsValue::UNDEFINED).is_err(), "the stepper needs supervisors");
    s.solve(JsValue::UNDEFINED, None).unwrap();
    let at = |trace: &str| s.step(js_sys::JSON::parse(trace).unwrap());
    let view = at(r#"["Tank.openInlet", "Tank.levelAlarm"]"#).unwrap();
    let events = array(&get(&view, "events"));
    let close = (0..events.length()).map(|i| events.get(i)).find(|e| string(e, "name") == "Tank.closeInlNow").unwrap();
    assert_eq!(string(&close, "status"), "enforced");
    assert_eq!(string(&close, "by"), "Safety.NoOverflow");
    let err = at(r#"["Tank.overflow"]"#).unwrap_err().as_string().unwrap();
    assert!(err.contains("rules it out"), "{err}");

    let cycles = js_sys::JSON::parse(
        r#"[{"elapsed_ms": 10, "controller": {"Q_Inlet": 1}},
            {"elapsed_ms": 10, "inputs": {"I_LevelHigh": 1}, "controller": {"Q_Inlet": 1}}]"#,
    )
    .unwrap();
    let run = s.cycles(cycles).unwrap();
    let cycles = array(&get(&run, "cycles"));
    assert_eq!(cycles.length(), 2);
    let second = cycles.get(1);
    let events = array(&get(&second, "events"));
    let what: Vec<String> = (0..events.length()).map(|i| string(&events.get(i), "what")).collect();
    assert!(what.contains(&"enforced".to_string()), "{what:?}");
    assert_eq!(num(&second, "time_ms"), 20.0);
    assert!(s.cycles(js_sys::JSON::parse(r#"[{"inputs": {"Nope": 1}}]"#).unwrap()).is_err());
}

const TWO_ROBOTS_13: &str = include_str!("../examples/timed/two_robots_13.tga");

/// The index of the offered move of `message` in a `SimState`.
fn sim_move(state: &JsValue, message: &str) -> usize {
    let moves = array(&get(state, "moves"));
    let m =
        moves.iter().find(|m| string(m, "message") == message).unwrap_or_else(|| panic!("{message} is not offered"));
    num(&m, "index") as usize
}

fn location(state: &JsValue, unit: &str) -> String {
    let l = array(&get(state, "locations")).iter().find(|l| string(l, "unit") == unit).unwrap();
    string(&l, "location")
}

#[wasm_bindgen_test]
fn the_simulator_steps_the_program_against_the_plant() {
    let (mut s, _) = solved(LAMP);
    assert!(s.sim_state().is_err(), "not started");
    let start = s.sim_start(1.0, JsValue::UNDEFINED).unwrap();
    assert_eq!(string(&start, "mode"), "program");
    assert!(array(&get(&start, "listing")).length() > 2, "the program's listing");
    assert_eq!(num(&start, "history"), 0.0);
    let pc = num(&start, "pc");
    let pressed = s.sim_step(sim_move(&start, "press")).unwrap();
    assert_eq!(array(&get(&pressed, "sent")).get(0).as_string().as_deref(), Some("turn_on"));
    assert_eq!(location(&pressed, "lamp"), "on");
    assert_eq!(num(&pressed, "progress"), 1.0);
    assert_ne!(num(&pressed, "pc"), pc, "the program moved on");
    assert!(get(&pressed, "listing").is_null(), "the listing comes with simStart only");
    assert_eq!(num(&pressed, "max_delay"), 0.875);
    assert!(s.sim_delay(2.0).is_err(), "beyond the invariant");
    let waited = s.sim_delay(0.5).unwrap();
    assert_eq!(num(&waited, "time"), 0.5);
    let events = array(&get(&waited, "events"));
    assert_eq!(events.length(), 3, "press, turn_on, the delay");
    assert_eq!(string(&events.get(2), "kind"), "delay");
    let located = array(&s.sim_locate().unwrap());
    assert!(located.length() >= 1);
    let first = located.get(0).as_f64().unwrap() as u32;
    assert_eq!(get(&s.state(first).unwrap(), "winning").as_bool(), Some(true));
    let back = s.sim_back().unwrap();
    assert_eq!(num(&back, "history"), 1.0);
    assert_eq!(num(&back, "time"), 0.0);
    let random = s.sim_random(40).unwrap();
    assert!(get(&random, "failure").is_null());
    assert_eq!(num(&random, "history"), 41.0);
    let restarted = s.sim_start(1.0, JsValue::UNDEFINED).unwrap();
    assert_eq!(num(&restarted, "history"), 0.0);
    // Started free, the requests are the user's.
    let free = s.sim_start(0.0, to_options(&[("free", JsValue::TRUE)])).unwrap();
    assert_eq!(string(&free, "mode"), "free");
    assert!(array(&get(&free, "moves")).iter().any(|m| string(&m, "kind") == "request"));
}

fn to_options(pairs: &[(&str, JsValue)]) -> JsValue {
    let o = js_sys::Object::new();
    for (k, v) in pairs {
        Reflect::set(&o, &JsValue::from_str(k), v).unwrap();
    }
    o.into()
}

#[wasm_bindgen_test]
fn an_unrealizable_spec_has_a_counter_play_the_simulator_replays() {
    let (mut s, summary) = solved(TWO_ROBOTS_13);
    assert_eq!(string(&summary, "verdict"), "unrealizable");
    let play = s.counter_play().unwrap();
    let moves = array(&get(&play, "moves"));
    assert_eq!(moves.length() as f64, num(&summary, "explanation_depth"));
    assert!(string(&play, "end").contains("fails"));
    let replayed = s.sim_replay().unwrap();
    assert_eq!(string(&replayed, "mode"), "free");
    let replay = get(&replayed, "replay");
    assert!(get(&replay, "stopped").is_null(), "the whole line is played");
    assert_eq!(num(&replay, "steps"), num(&replayed, "history"));
    assert_eq!(string(&get(&replayed, "failure"), "kind"), "plan_failed");
    assert!(s.sim_step(0).is_err(), "the simulation has ended");
    let back = s.sim_back().unwrap();
    assert!(get(&back, "failure").is_null());
    // A realizable spec has none.
    let (mut lamp, _) = solved(LAMP);
    assert!(lamp.counter_play().unwrap().is_null());
    assert!(lamp.sim_replay().is_err());
}

#[wasm_bindgen_test]
fn the_editor_check_of_a_large_sct_product_stops_early_with_a_warning() {
    // Six independent cycles of eight states: a product of 262 144 states, over the check's
    // budget of 200 000.
    let mut text = String::new();
    for i in 0..6 {
        text.push_str(&format!("event e{i} : controllable;\nspec S{i} {{\n"));
        for j in 0..8 {
            text.push_str(&format!("  state A{j} {{ e{i} -> A{}; }}\n", (j + 1) % 8));
        }
        text.push_str("}\n");
    }
    text.push_str("spec P = S0 | S1 | S2 | S3 | S4 | S5;\n");
    let result = check("sct", &text).unwrap();
    assert_eq!(get(&result, "ok").as_bool(), Some(true), "a large product is no mistake");
    let diags = array(&get(&result, "diagnostics"));
    assert_eq!(diags.length(), 1);
    let d = diags.get(0);
    assert_eq!(string(&d, "severity"), "warning");
    assert!(string(&d, "message").contains("Run builds it"));
    assert_eq!(num(&d, "line"), 67.0, "located at the product");
}

/// A file for `importModel`: `{ name, bytes, kind }`.
fn model_file(name: &str, bytes: &[u8], kind: &str) -> JsValue {
    to_options(&[
        ("name", JsValue::from_str(name)),
        ("bytes", js_sys::Uint8Array::from(bytes).into()),
        ("kind", JsValue::from_str(kind)),
    ])
}

/// What `importModel` throws, with its first diagnostic.
fn import_error(files: &[JsValue], options: &str) -> (JsValue, JsValue) {
    let list: Array = files.iter().collect();
    let err = import_model(list, js_sys::JSON::parse(options).unwrap()).expect_err("the import must fail");
    assert_eq!(get(&err, "ok").as_bool(), Some(false));
    let first = array(&get(&err, "diagnostics")).get(0);
    (err, first)
}

/// Synthesises an imported project: the verdict of each supervisor.
fn supervisors_of(text: &str) -> Vec<(String, bool)> {
    let mut s = SctSession::new(text, JsValue::UNDEFINED).map_err(|e| format!("{e:?}\n{text}")).unwrap();
    let summary = s.solve(JsValue::UNDEFINED, None).unwrap();
    assert!(get(&summary, "stop").is_null());
    array(&get(&summary, "supervisors"))
        .iter()
        .map(|x| (string(&x, "name"), get(&x, "realizable").as_bool().unwrap()))
        .collect()
}

#[wasm_bindgen_test]
fn import_model_converts_a_supremica_module_into_a_project_that_synthesises() {
    // Supremica writes windows-1252: an event `sé` (0xE9) must arrive decoded, then renamed.
    let module = include_str!("fixtures/wmod/small_factory.wmod").replace("Name=\"s1\"", "Name=\"s\u{e9}\"");
    let bytes: Vec<u8> = module.chars().map(|c| u8::try_from(u32::from(c)).expect("Latin-1")).collect();
    assert!(std::str::from_utf8(&bytes).is_err(), "the module is not UTF-8");
    let file = model_file("small_factory.wmod", &bytes, "plant");
    // Its machines' working states are unmarked: refused, located in the module.
    let (err, d) = import_error(std::slice::from_ref(&file), "{}");
    assert_eq!(string(&d, "file"), "small_factory.wmod");
    assert_eq!((num(&d, "line"), num(&d, "column")), (43.0, 19.0));
    assert_eq!(string(&d, "severity"), "error");
    assert_eq!(string(&d, "message"), "state `W` of `M1` is not marked");
    let note = array(&get(&d, "notes")).get(0).as_string().unwrap();
    assert!(note.contains("`Ignore marking` reads every state as marked"), "{note}");
    assert_eq!(get(&err, "unmarked").as_bool(), Some(true));
    let rendered = string(&d, "rendered");
    assert!(rendered.contains("small_factory.wmod:43:19: error: state `W` of `M1` is not marked"), "{rendered}");
    assert!(rendered.contains("43 | <SimpleNode Name=\"W\">"), "{rendered}");
    // With marking ignored it converts: the header says so and lists the renamed event.
    let list: Array = [file].into_iter().collect();
    let imported = import_model(list, js_sys::JSON::parse(r#"{"ignoreMarking": true}"#).unwrap()).unwrap();
    assert_eq!(string(&imported, "name"), "small_factory.sct");
    let text = string(&imported, "text");
    assert!(text.starts_with("// Imported by the plcsynth playground from `small_factory.wmod`."), "{text}");
    assert!(text.contains("// Marking ignored (Ignore marking): every state is read as marked."), "{text}");
    assert!(text.contains("//   `s\u{e9}` is `s_`"), "{text}");
    assert!(text.contains("state I initial { s_ -> W; }"), "{text}");
    assert!(text.contains("spec Buffer {\n  state empty initial { f1 -> full; forbid s2; }"), "{text}");
    // The project checks and synthesises in the page's engine: the buffer's supervisor exists.
    assert_eq!(get(&check("sct", &text).unwrap(), "ok").as_bool(), Some(true));
    let sups = supervisors_of(&text);
    assert!(!sups.is_empty() && sups.iter().all(|(_, ok)| *ok), "{sups:?}");
}

#[wasm_bindgen_test]
fn import_model_reads_generators_as_plants_and_specifications() {
    let machine = "<Generator> \"M1\"\n<Alphabet> a1 +C+ b1 </Alphabet>\n<States> idle busy </States>\n\
                   <TransRel>\nidle a1 busy\nbusy b1 idle\n</TransRel>\n<InitStates> idle </InitStates>\n\
                   <MarkedStates> idle busy </MarkedStates>\n</Generator>\n";
    // At most one part in the buffer: start again (a1) only after the part was taken (b1).
    let once = "<Generator> \"Once\"\n<Alphabet> a1 +C+ b1 </Alphabet>\n<States> ready started </States>\n\
                <TransRel>\nready a1 started\nstarted b1 ready\n</TransRel>\n<InitStates> ready </InitStates>\n\
                <MarkedStates> ready started </MarkedStates>\n</Generator>\n";
    let files: Array =
        [model_file("machine.gen", machine.as_bytes(), "plant"), model_file("once.gen", once.as_bytes(), "spec")]
            .into_iter()
            .collect();
    let imported = import_model(files, JsValue::UNDEFINED).unwrap();
    assert_eq!(string(&imported, "name"), "machine.sct");
    let text = string(&imported, "text");
    assert!(text.starts_with("// Imported by the plcsynth playground from `machine.gen`, `once.gen`."), "{text}");
    assert!(text.contains("plant machine {") && text.contains("spec once {"), "{text}");
    assert!(text.contains("event a1 : controllable;") && text.contains("event b1 : uncontrollable;"), "{text}");
    assert_eq!(supervisors_of(&text), vec![("once".to_string(), true)]);
    // A generator's error is located in its own file.
    let broken = machine.replace("busy b1 idle", "busy b1 nowhere");
    let files =
        [model_file("machine.gen", broken.as_bytes(), "plant"), model_file("once.gen", once.as_bytes(), "spec")];
    let (err, d) = import_error(&files, "{}");
    assert_eq!(string(&d, "file"), "machine.gen");
    assert_eq!(num(&d, "line"), 6.0);
    assert!(string(&d, "message").contains("nowhere"), "{}", string(&d, "message"));
    assert!(string(&d, "rendered").starts_with("machine.gen:6:"), "{}", string(&d, "rendered"));
    assert_eq!(get(&err, "unmarked").as_bool(), Some(false));
}

#[wasm_bindgen_test]
fn import_model_locates_malformed_modules_and_refuses_what_it_cannot_read() {
    let module = "<?xml version=\"1.0\"?>\n<Module xmlns=\"http://waters.sourceforge.net/xsd/module\" Name=\"m\">\n\
                  <EventDeclList>\n<EventDecl Kind=\"CONTROLLABLE\" Name=\"a\">\n</EventDeclList>\n</Module>\n";
    let (_, d) = import_error(&[model_file("bad.wmod", module.as_bytes(), "plant")], "{}");
    assert_eq!(string(&d, "file"), "bad.wmod");
    assert_eq!((num(&d, "line"), num(&d, "column")), (5.0, 1.0));
    assert!(string(&d, "message").starts_with("malformed XML"), "{}", string(&d, "message"));
    assert!(string(&d, "rendered").starts_with("bad.wmod:5:1: error: malformed XML"), "{}", string(&d, "rendered"));
    // Bytes that are no text, a file of another kind, two modules at once: said, not thrown as text.
    let (_, d) = import_error(&[model_file("x.gen", &[0xff, 0xfe, 0x00, 0x41], "plant")], "{}");
    assert!(string(&d, "message").contains("is not UTF-8 text"), "{}", string(&d, "message"));
    let (_, d) = import_error(&[model_file("notes.txt", b"hello", "plant")], "{}");
    assert!(string(&d, "message").contains("neither a Supremica module"), "{}", string(&d, "message"));
    let good = include_bytes!("fixtures/wmod/small_factory.wmod");
    let (_, d) = import_error(&[model_file("a.wmod", good, "plant"), model_file("b.wmod", good, "plant")], "{}");
    assert!(string(&d, "message").contains("one `.wmod` module at a time"), "{}", string(&d, "message"));
    // Wrong arguments are the caller's mistake: thrown as text.
    assert!(import_model(Array::new(), JsValue::UNDEFINED).unwrap_err().as_string().unwrap().contains("no file"));
    let odd: Array = [model_file("x.gen", b"", "supervisor")].into_iter().collect();
    assert!(import_model(odd, JsValue::UNDEFINED).unwrap_err().as_string().unwrap().contains("unknown kind"));
}
