//! Controller programs (Peter 2005, chapter 6): the thesis's expected programs and every
//! optimisation rule with the before/after examples of 6.6.

use plcsynth::timed::model::{ClockId, Game};
use plcsynth::timed::program::optimize::{self, Context};
use plcsynth::timed::program::{self as prog, parse_listing, Program};
use plcsynth::timed::{compile, solve::Config, synthesize};

fn read(path: &str) -> String {
    std::fs::read_to_string(format!("{}/{path}", env!("CARGO_MANIFEST_DIR"))).unwrap()
}

fn game_of(source: &str) -> Game {
    compile(source).unwrap_or_else(|d| panic!("{d:?}")).0
}

/// The program from the thesis's algorithm: its listings come from request selection over the
/// whole winning space, which the exhaustive reference computes (the default search keeps only
/// the states of one strategy, and its programs can differ, see `tests/random_specs.rs`).
fn controller(path: &str) -> (Game, Program) {
    controller_from(path, true)
}

/// The program from the default search (`exhaustive` false) or from the reference.
fn controller_from(path: &str, exhaustive: bool) -> (Game, Program) {
    let game = game_of(&read(path));
    let s = synthesize(&game, &Config { exhaustive, ..Config::default() }, &mut |_| true);
    let program = prog::controller(&game, &s).expect("realizable");
    (game, program)
}

/// Parses a listing, renaming the thesis's message names with `rename`.
fn listing(game: &Game, text: &str, rename: &dyn Fn(&str) -> String) -> Program {
    parse_listing(text, &|m| game.message_id(&rename(m)), &|c| {
        game.clocks.iter().position(|k| k.name == c).map(ClockId::new)
    })
    .unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn lamp_is_the_five_line_program_of_7_2_1() {
    let (game, program) = controller("examples/timed/lamp.tga");
    assert_eq!(
        program.render(&game),
        "0 : WAITUNTIL (press);\n1 : DO (turn_on);\n2 : WAITUNTIL (release);\n3 : DO (turn_off);\n4 : GOTO 0;\n"
    );
    let thesis = listing(&game, &read("tests/fixtures/thesis/lamp_program.txt"), &|m| m.to_string());
    assert!(optimize::equivalent(&thesis, &program));
}

#[test]
fn gear_checking_machine_is_the_thirty_line_program_of_7_2_2() {
    let (game, program) = controller("examples/timed/gear_checking.tga");
    let thesis = listing(&game, &read("tests/fixtures/thesis/gcm_program.txt"), &|m| m.to_string());
    assert_eq!(program.len(), 30, "{}", program.render(&game));
    assert!(optimize::equivalent(&thesis, &program), "{}", program.render(&game));
}

#[test]
fn round_table_with_one_bin_has_the_structure_of_appendix_a() {
    let (game, program) = controller("examples/timed/round_table_1.tga");
    // The generated example numbers the bin's messages (`classify_0`); the thesis does not.
    let rename = |m: &str| {
        if m.starts_with("c0_is_") || m == "cycle" || m == "cycle_end" {
            m.to_string()
        } else {
            format!("{m}_0")
        }
    };
    let thesis = listing(&game, &read("tests/fixtures/thesis/rt1_program.txt"), &rename);
    assert_eq!(thesis.len(), 41);
    assert_eq!(program.len(), 41, "{}", program.render(&game));
    assert!(optimize::equivalent(&thesis, &program), "{}", program.render(&game));
}

#[test]
fn unrealizable_specifications_have_no_program() {
    let game = game_of(&read("examples/timed/lamp_naive.tga"));
    let s = synthesize(&game, &Config::default(), &mut |_| true);
    assert!(prog::controller(&game, &s).is_none());
}

#[test]
fn equivalence_notices_a_different_action() {
    let (game, program) = controller("examples/timed/gear_checking.tga");
    let text = read("tests/fixtures/thesis/gcm_program.txt").replace("DO (moveto_outtake)", "DO (moveto_intake)");
    let changed = listing(&game, &text, &|m| m.to_string());
    assert!(!optimize::equivalent(&changed, &program));
}

// ----- the rules of 6.6, each with the thesis's example --------------------------------------

const ABC: &str = "plant { automaton u { nodes q; q -> q ?A; q -> q ?B; q -> q ?C; q -> q !D; q -> q !E; } }\nplans { plan { waitfor A; } }\n";

fn abc() -> Game {
    game_of(ABC)
}

fn p(game: &Game, text: &str) -> Program {
    listing(game, text, &|m| m.to_string())
}

fn show(game: &Game, program: &Program) -> String {
    program.render(game).replace('\n', " ")
}

#[test]
fn rule_6_6_1_waituntil_replacement() {
    let g = abc();
    let mut program = p(&g, "1: IF (D) THEN 10; 2: GOTO 1; 10: DO (A); 11: GOTO 1;");
    assert!(optimize::waituntil_replacement(&mut program));
    assert_eq!(show(&g, &program), "0 : WAITUNTIL (D); 1 : GOTO 2; 2 : DO (A); 3 : GOTO 0; ");
}

#[test]
fn rule_6_6_2_inlining() {
    let g = abc();
    let mut program = p(&g, "1: GOTO 10; 2: DO (B); 3: GOTO 1; 10: DO (A); 11: GOTO 20; 20: DO (C); 21: GOTO 2;");
    assert!(optimize::inlining(&mut program));
    // `1: GOTO 10` becomes `1: DO (A); 1.5: GOTO 20`; the original block stays until removed. In
    // the same pass `21: GOTO 2` (block `2` is referenced once) becomes `DO (B); GOTO 1`.
    assert_eq!(
        show(&g, &program),
        "0 : DO (A); 1 : GOTO 6; 2 : DO (B); 3 : GOTO 0; 4 : DO (A); 5 : GOTO 6; 6 : DO (C); 7 : DO (B); 8 : GOTO 0; "
    );
}

#[test]
fn rule_6_6_2_does_not_inline_a_block_with_other_references() {
    let g = abc();
    let mut program = p(&g, "1: GOTO 10; 2: IF (D) THEN 10; 3: GOTO 1; 10: DO (A); 11: GOTO 1;");
    assert!(!optimize::inlining(&mut program));
}

#[test]
fn rule_6_6_3_reference_inlining() {
    let g = abc();
    let mut program = p(&g, "1: IF (D) THEN 10; 2: GOTO 1; 10: GOTO 20; 20: DO (A); 21: GOTO 1;");
    assert!(optimize::reference_inlining(&mut program));
    assert_eq!(show(&g, &program), "0 : IF (D) THEN GOTO 3; 1 : GOTO 0; 2 : GOTO 3; 3 : DO (A); 4 : GOTO 0; ");
}

#[test]
fn rule_6_6_4_unreachable_block_removal() {
    let g = abc();
    let mut program = p(&g, "10: GOTO 13; 11: DO (A); 12: DO (B); 13: DO (C); 14: GOTO 10;");
    assert!(optimize::unreachable_removal(&mut program));
    assert_eq!(show(&g, &program), "0 : GOTO 2; 1 : DO (B); 2 : DO (C); 3 : GOTO 0; ");
}

#[test]
fn rule_6_6_5_redundant_goto_removal() {
    let g = abc();
    let mut program = p(&g, "10: DO (A); 11: GOTO 12; 12: DO (B); 13: DO (C); 14: GOTO 10;");
    assert!(optimize::redundant_goto_removal(&mut program));
    assert_eq!(show(&g, &program), "0 : DO (A); 1 : DO (B); 2 : DO (C); 3 : GOTO 0; ");
}

fn context_with(game: &Game, dependencies: &str) -> Context {
    let spec = format!("{ABC}dependencies {{ {dependencies} }}\n");
    let g = game_of(&spec);
    let mut cx = Context::from_game(&g);
    cx.observable = vec![true; game.messages.len()];
    cx
}

#[test]
fn rule_6_6_6_redundant_if_removal_uses_the_dependencies() {
    let g = abc();
    // D depends only on A: after `IF (D)` failed, a second test before `DO (A)` is redundant,
    // and a test right after a jump on D is known to succeed.
    let cx = context_with(&g, "D dependson A;");
    let mut program = p(&g, "0: DO (B); 1: IF (D) THEN 5; 2: IF (D) THEN 8; 3: DO (C); 4: GOTO 0; 5: IF (D) THEN 7; 6: GOTO 0; 7: DO (A); 8: GOTO 0;");
    assert!(optimize::redundant_if_removal(&mut program, &cx));
    assert_eq!(
        show(&g, &program),
        "0 : DO (B); 1 : IF (D) THEN GOTO 4; 2 : DO (C); 3 : GOTO 0; 4 : GOTO 6; 5 : GOTO 0; 6 : DO (A); 7 : GOTO 0; "
    );
}

#[test]
fn rule_6_6_6_keeps_tests_whose_outcome_may_have_changed() {
    let g = abc();
    // D depends on time, and a WAITUNTIL lets time pass between the two tests.
    let cx = context_with(&g, "D dependson time;");
    let mut program = p(&g, "0: IF (D) THEN 4; 1: WAITUNTIL (E); 2: IF (D) THEN 4; 3: GOTO 0; 4: DO (A); 5: GOTO 0;");
    assert!(!optimize::redundant_if_removal(&mut program, &cx));
    // Without any declaration a message may change with any request: nothing is removed either.
    let cx = context_with(&g, "E dependson time;");
    let mut program =
        p(&g, "0: DO (B); 1: IF (D) THEN 5; 2: DO (C); 3: IF (D) THEN 5; 4: GOTO 0; 5: DO (A); 6: GOTO 0;");
    assert!(!optimize::redundant_if_removal(&mut program, &cx));
    // Within one scan nothing changes: a repeated test is redundant even then.
    let mut program = p(&g, "0: DO (B); 1: IF (D) THEN 4; 2: IF (D) THEN 4; 3: GOTO 0; 4: DO (A); 5: GOTO 0;");
    assert!(optimize::redundant_if_removal(&mut program, &cx));
    assert_eq!(show(&g, &program), "0 : DO (B); 1 : IF (D) THEN GOTO 3; 2 : GOTO 0; 3 : DO (A); 4 : GOTO 0; ");
}

#[test]
fn silent_waits_are_dropped_only_before_observable_waits() {
    // D is not bound in the io section, so the PLC cannot see it.
    let spec = format!("{ABC}io {{ A = %Q0.0; B = %Q0.1; C = %Q0.2; E = %I0.0; }}\n");
    let g = game_of(&spec);
    let cx = Context::from_game(&g);
    let mut program = p(&g, "0: DO (A); 1: WAITUNTIL (D); 2: WAITUNTIL (E); 3: GOTO 0;");
    assert!(optimize::silent_wait_removal(&mut program, &cx));
    assert_eq!(show(&g, &program), "0 : DO (A); 1 : WAITUNTIL (E); 2 : GOTO 0; ");
    // Before an action the wait must stay: the controller would act too early.
    let mut program = p(&g, "0: DO (A); 1: WAITUNTIL (D); 2: DO (B); 3: GOTO 0;");
    assert!(!optimize::silent_wait_removal(&mut program, &cx));
}

#[test]
fn merging_folds_an_unrolled_loop() {
    let g = abc();
    let mut program = p(&g, "0: DO (A); 1: WAITUNTIL (D); 2: DO (B); 3: WAITUNTIL (E); 4: DO (A); 5: WAITUNTIL (D); 6: DO (B); 7: WAITUNTIL (E); 8: GOTO 4;");
    let before = program.clone();
    assert!(optimize::merge_equivalent(&mut program));
    optimize::optimize(&mut program, &Context::from_game(&g));
    assert_eq!(show(&g, &program), "0 : DO (A); 1 : WAITUNTIL (D); 2 : DO (B); 3 : WAITUNTIL (E); 4 : GOTO 0; ");
    assert!(optimize::equivalent(&before, &program));
}

#[test]
fn optimisation_preserves_behaviour_on_every_example() {
    use plcsynth::timed::program::{generate, select};
    for name in [
        "lamp",
        "gear_checking",
        "round_table_1",
        "round_table_2",
        "two_robots_14",
        "robot_arm",
        "gripper_guard",
        "hardware_xyz",
    ] {
        let game = game_of(&read(&format!("examples/timed/{name}.tga")));
        let s = synthesize(&game, &Config::default(), &mut |_| true);
        let strategy = select::select(&game, &s.solution.space);
        let raw = generate::generate(&game, &s.split, &s.solution.space, &strategy).program;
        // Without the observation rules (everything observable, nothing urgent) the six rules
        // of the thesis and the folding must not change what the program does.
        let mut cx = Context::from_game(&game);
        cx.observable = vec![true; game.messages.len()];
        cx.urgent = vec![false; game.messages.len()];
        cx.silent_delays = false;
        cx.declared = vec![false; game.messages.len()];
        let mut optimised = raw.clone();
        optimize::optimize(&mut optimised, &cx);
        optimize::drop_unread_resets(&mut optimised);
        let mut raw_no_resets = raw.clone();
        optimize::drop_unread_resets(&mut raw_no_resets);
        assert!(optimize::equivalent(&raw_no_resets, &optimised), "{name}:\n{}", optimised.render(&game));
        assert!(optimised.len() <= raw.len(), "{name}");
    }
}

// ----- closed loop: the generated program against the plant -------------------------------------

#[test]
fn generated_programs_keep_the_plant_safe_and_progressing_in_1000_random_runs() {
    use plcsynth::timed::program::simulate;
    for name in [
        "lamp",
        "gear_checking",
        "round_table_1",
        "round_table_2",
        "round_table_3",
        "two_robots_14",
        "two_robots_22",
        "robot_arm",
        "gripper_guard",
        "hardware_xyz",
    ] {
        for exhaustive in [false, true] {
            let (game, program) = controller_from(&format!("examples/timed/{name}.tga"), exhaustive);
            let observable = Context::from_game(&game).observable;
            let mut progress = 0;
            for seed in 0..1000u64 {
                let report = simulate::run(&game, &program, &observable, seed, 300);
                assert!(
                    report.failure.is_none(),
                    "{name} (exhaustive: {exhaustive}), seed {seed}: {:?}\n{}\nprogram:\n{}",
                    report.failure,
                    report.trace.join("\n"),
                    program.render(&game)
                );
                progress += report.progress;
            }
            assert!(progress > 1000, "{name}: the plans progressed only {progress} times in 1000 runs");
        }
    }
}

#[test]
fn the_checker_catches_a_wrong_program() {
    use plcsynth::timed::program::simulate::{self, Failure};
    // Swapping the lamp's actions violates the assertions at once.
    let game = game_of(&read("examples/timed/lamp.tga"));
    let wrong = listing(&game, "0: WAITUNTIL (press); 1: DO (turn_off); 2: GOTO 0;", &|m| m.to_string());
    let observable = Context::from_game(&game).observable;
    let failures = (0..50).filter_map(|seed| simulate::run(&game, &wrong, &observable, seed, 100).failure).count();
    assert!(failures > 0);
    // A GCM program that forgets to lift the gripper before moving it crashes into the obstacle.
    let game = game_of(&read("examples/timed/gear_checking.tga"));
    let text = read("tests/fixtures/thesis/gcm_program.txt").replace("3 :   WAITUNTIL (reached_up);\n", "");
    let wrong = listing(&game, &text, &|m| m.to_string());
    let report = simulate::run(&game, &wrong, &Context::from_game(&game).observable, 1, 100);
    assert!(matches!(report.failure, Some(Failure::Assertion { .. })), "{report:?}");
    // Waiting for an event that already happened stalls the machine until the plan times out.
    let text = read("tests/fixtures/thesis/gcm_program.txt")
        .replace("3 :   WAITUNTIL (reached_up);", "3 :   WAITUNTIL (loaded);");
    let wrong = listing(&game, &text, &|m| m.to_string());
    let report = simulate::run(&game, &wrong, &Context::from_game(&game).observable, 1, 100);
    assert!(matches!(report.failure, Some(Failure::PlanFailed { .. })), "{report:?}");
}
