//! The `.tga` language: the thesis listings, located diagnostics, robustness.

use plcsynth::diag::render_plain;
use plcsynth::timed::{compile, parse};

fn fixture(name: &str) -> String {
    std::fs::read_to_string(format!("{}/tests/fixtures/thesis/{name}", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

fn syntax_errors(src: &str) -> Vec<String> {
    parse(src).diagnostics.iter().filter(|d| d.is_error()).map(|d| format!("{}:{}: {}", d.line, d.column, d.message)).collect()
}

#[test]
fn thesis_listings_parse_verbatim() {
    for name in ["round_table_appendix_a.tga", "robot_arm_4_1_4.tga", "robot_arm_4_1_4_bare.tga", "gripper_4_2_1.tga", "plan_4_2_2.tga"] {
        let src = fixture(name);
        assert_eq!(syntax_errors(&src), Vec::<String>::new(), "{name}");
    }
}

#[test]
fn thesis_listings_with_a_plant_check() {
    for name in ["round_table_appendix_a.tga", "robot_arm_4_1_4.tga", "robot_arm_4_1_4_bare.tga", "gripper_4_2_1.tga"] {
        let src = fixture(name);
        if let Err(d) = compile(&src) {
            panic!("{name}:\n{}", render_plain(name, &src, &d));
        }
    }
}
