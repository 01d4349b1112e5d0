//! The step machine the timed lowering builds before it writes the unit: a function block with
//! BOOL inputs and outputs, timers, and a list of steps (statements over tests) with the
//! signals' bindings. Here the lowering decides which requests and backward transfers go on
//! within their scan ([`chain_requests`]); [`super::structured`] then turns the machine into a
//! [`crate::plc::model::unit::Unit`], the form every printer and the interpreter read.

use crate::diag::Span;

/// Where a signal lives outside the block.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Binding {
    /// A direct address such as `I0.0`, `QX1.3`, `MX10.2` (without the `%`).
    Address(String),
    /// A symbol of an existing project, possibly dotted (`GVL.lamp`).
    Symbol(String),
    /// A Siemens tag name written in quotes (`"Lamp On"`), printed with its quotes.
    Quoted(String),
}

/// Which way a signal flows, seen from the PLC program.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    Input,
    Output,
}

/// A BOOL variable of the block's interface.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Variable {
    /// A valid IEC identifier (see [`crate::plc::identifier`]).
    pub symbol: String,
    /// The signal it is wired to, if any; unbound variables are the block's own inputs/outputs.
    pub binding: Option<Binding>,
    /// What the variable stands for, printed beside its declaration.
    pub comment: String,
    /// Where the binding is written in the source, for diagnostics about it.
    pub span: Option<Span>,
}

impl Variable {
    /// A variable of the block's own interface, wired to nothing, without comment.
    pub fn unbound(symbol: &str) -> Variable {
        Variable { symbol: symbol.into(), binding: None, comment: String::new(), span: None }
    }
}

/// An output variable.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Output {
    pub variable: Variable,
    /// Pulsed outputs are cleared at the start of every scan.
    pub pulsed: bool,
    /// For a pulsed output: a BOOL of the block that holds the output's value at the last
    /// output write, captured at the start of every scan before the clear. A pulse while it is
    /// TRUE (the output was pulsed in the previous scan) does not act: the step ends the scan
    /// and pulses in the next one, so the machine sees a FALSE write, and a rising edge, for
    /// every pulse. The lowering gives every pulsed output one; without it (`None`) two pulses
    /// in consecutive scans keep the output TRUE and are one request for the machine.
    pub last: Option<String>,
}

impl Output {
    /// The memory of the last write, if the output is pulsed and has one.
    pub fn gap(&self) -> Option<&str> {
        self.last.as_deref().filter(|_| self.pulsed)
    }
}

/// An on-delay timer (`TON`), running while the block runs and restarted by steps.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Timer {
    pub symbol: String,
    /// What it measures, printed beside its declaration.
    pub comment: String,
    /// The preset: above the largest threshold compared (see [`crate::plc::TimeType`]).
    pub preset_ms: u64,
}

/// A condition a step tests.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Test {
    /// Input `input` is TRUE (or FALSE when `negated`).
    Input { input: usize, negated: bool },
    /// Timer `timer` has run at least `ms` (more than `ms` when `strict`).
    Elapsed { timer: usize, ms: u64, strict: bool },
}

/// What a step does to its output.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Effect {
    /// TRUE for this scan (one scan later if the output was TRUE in the previous one).
    Pulse,
    Set,
    Reset,
}

/// What one program position does.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Statement {
    /// Wait until `test` holds, then continue at the next position.
    Wait { test: Test },
    /// If `test` holds, continue at `target`, else at the next position.
    Branch { test: Test, target: usize },
    /// Drive an output and continue at the next position: in the next scan when `ends_scan`,
    /// else within this one. A pulse of an output that was TRUE at the last write (see
    /// [`Output::last`]) only ends the scan and stays at this position.
    ///
    /// A request may go on within its scan only where nothing later in the scan depends on it
    /// having taken effect: the input image is the one latched before the request, and every
    /// output is written at the end of the scan at once. [`chain_requests`] decides it.
    Act { output: usize, effect: Effect, ends_scan: bool },
    /// Continue at `target`.
    Jump { target: usize },
}

/// One program position.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Step {
    pub statement: Statement,
    /// Timers restarted when the step takes effect (its test holds, or it acts or jumps).
    pub restarts: Vec<usize>,
    /// The source of the step (an intermediate command), printed beside it.
    pub comment: String,
    /// For a jump or branch to a position not after it (a backward transfer): whether the scan
    /// goes on at the target instead of ending there. [`chain_requests`] allows it only where
    /// the scan cannot come back again (nothing loops within a scan) and no request that goes
    /// on can reach the step in its scan.
    pub back_in_scan: bool,
}

impl Step {
    /// A step without comment.
    pub fn new(statement: Statement, restarts: Vec<usize>) -> Step {
        Step { statement, restarts, comment: String::new(), back_in_scan: false }
    }

    /// Where the step transfers control backwards (to a position not after `at`, its own),
    /// when it is a jump or a branch taken.
    pub fn backward_target(&self, at: usize) -> Option<usize> {
        match self.statement {
            Statement::Branch { target, .. } | Statement::Jump { target } if target <= at => Some(target),
            _ => None,
        }
    }
}

/// A function block: everything the printers need.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Code {
    /// Identifier of the function block.
    pub name: String,
    /// Identifier of the program (or wrapper block) that instantiates and wires the block.
    pub program: String,
    /// Identifier of the block's instance inside [`Code::program`].
    pub instance: String,
    /// Identifier of the global variable list of the I/O (CODESYS, TwinCAT).
    pub gvl: String,
    /// Comment lines for the head of every file.
    pub header: Vec<String>,
    pub inputs: Vec<Variable>,
    pub outputs: Vec<Output>,
    pub timers: Vec<Timer>,
    pub steps: Vec<Step>,
}

impl Code {
    /// Where execution goes on after it reaches position `i` by falling through: through jumps
    /// without restarts (they do nothing but jump), and past the last step at 0. This is the
    /// position every printer stores when a scan ends before `i`, so that no scan is spent on a
    /// bare jump.
    pub fn resume_at(&self, mut i: usize) -> usize {
        let n = self.steps.len();
        let mut hops = 0;
        while i < n && hops <= n {
            match self.steps[i].statement {
                Statement::Jump { target } if self.steps[i].restarts.is_empty() => {
                    i = target;
                    hops += 1;
                }
                _ => break,
            }
        }
        if i >= n {
            0
        } else {
            i
        }
    }

    /// Every interface variable with its direction: inputs first, then outputs.
    pub fn variables(&self) -> impl Iterator<Item = (&Variable, Direction)> {
        let inputs = self.inputs.iter().map(|v| (v, Direction::Input));
        inputs.chain(self.outputs.iter().map(|o| (&o.variable, Direction::Output)))
    }
}

/// What a lowering knows of the request an [`Statement::Act`] step sends, for
/// [`chain_requests`].
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct RequestFacts {
    /// The inputs whose level may change as soon as the request takes effect (its feedback).
    pub feedback: Vec<usize>,
    /// Tokens of what the request touches (parts of the machine, and rules over them), opaque
    /// here: two requests whose tokens meet might not commute, and never share a scan.
    pub footprint: Vec<u32>,
}

/// How far [`chain_requests`] looks ahead of a request within its scan; a scan that could run
/// further ends after the request.
const LOOK_AHEAD: usize = 256;

/// Lets every request go on within its scan where that is sound, and ends the scan after the
/// others: sets `ends_scan` of each [`Statement::Act`] step. `facts` holds per step the facts
/// of the request it sends (`None`: unknown, the scan ends).
///
/// A scan reads its inputs once, at its start, and writes all outputs at its end, together. So
/// a request may go on only if, on every way the scan can run on from it, no test reads one of
/// its feedback inputs (the image still shows the machine before the request), no later
/// request drives the same output (a pulse needs a FALSE write between two pulses, and a set
/// and reset in one scan cancel out), and every later request commutes with it (the machine
/// may take the requests of one write in any order). Within a scan the position only grows,
/// so the steps are decided from the last to the first, each against the decisions after it.
/// Timer tests need no care: a timer restarted by the request reads 0 for the rest of the
/// scan, as its clock does; so a test that it has run a positive time is false, and the scan
/// cannot pass it.
///
/// Then the backward transfers: a jump or taken branch back to `t` goes on at `t` within the
/// scan ([`Step::back_in_scan`]) when no way the scan can run on from `t` transfers control
/// backwards again, so that it passes at most one backward transfer and still ends, and when no
/// request that goes on can reach the transfer in its scan (its decision assumed the scan ends
/// there). A backward transfer is a loop of the program's: it reads nothing new, so going on
/// is the same as resuming at `t` in the next scan, a scan earlier.
pub fn chain_requests(code: &mut Code, facts: &[Option<RequestFacts>]) {
    let n = code.steps.len();
    for i in (0..n).rev() {
        let Statement::Act { output, .. } = code.steps[i].statement else { continue };
        let goes_on =
            facts.get(i).and_then(Option::as_ref).is_some_and(|mine| !scan_depends_on(code, facts, i, output, mine));
        if let Statement::Act { ends_scan, .. } = &mut code.steps[i].statement {
            *ends_scan = !goes_on;
        }
    }
    // Positions a request that goes on may reach within its scan.
    let mut after_request = vec![false; n];
    let mut complete = true;
    for i in 0..n {
        if matches!(code.steps[i].statement, Statement::Act { ends_scan: false, .. }) {
            complete &= walk_scan(code, i + 1, &code.steps[i].restarts, |p, _| {
                after_request[p] = true;
                true
            });
        }
    }
    // With a request's scan not followed to its end, no backward transfer is known safe.
    let backs: Vec<bool> = (0..n)
        .map(|j| {
            complete
                && !after_request[j]
                && code.steps[j].backward_target(j).is_some_and(|t| {
                    // Within the look-ahead, and no backward transfer on the way.
                    walk_scan(code, t, &code.steps[j].restarts, |p, step| step.backward_target(p).is_none())
                })
        })
        .collect();
    for (step, back) in code.steps.iter_mut().zip(backs) {
        step.back_in_scan = back;
    }
}

/// Walks the positions a scan may run through from `start` on, when the timers in `restarted`
/// were restarted earlier in the scan: forward only (backward transfers end the walk; the
/// callers decide where they may not), a wait passes unless it tests that a timer restarted
/// on the way has run a positive time (it reads 0 for the rest of the scan), a branch goes
/// either way (not to its target on such a test), a request that goes on continues. Calls
/// `visit` on each position; stops and returns false when `visit` does or the walk passes
/// [`LOOK_AHEAD`] positions, else returns true. Positions are told apart by the timers
/// restarted on the way to them, so the pruning is exact per path.
fn walk_scan(code: &Code, start: usize, restarted: &[usize], mut visit: impl FnMut(usize, &Step) -> bool) -> bool {
    let n = code.steps.len();
    // Timers as a bit set; beyond 64 timers nothing is pruned.
    let bits = |timers: &[usize]| timers.iter().filter(|&&t| t < 64).fold(0u64, |b, &t| b | 1 << t);
    let false_now = |test: &Test, r: u64| matches!(*test, Test::Elapsed { timer, ms, strict } if timer < 64 && r >> timer & 1 == 1 && (ms > 0 || strict));
    let mut seen = std::collections::HashSet::new();
    let mut todo = vec![(start, bits(restarted))];
    let mut visited = 0;
    while let Some((p, r)) = todo.pop() {
        if p >= n || !seen.insert((p, r)) {
            continue;
        }
        visited += 1;
        let step = &code.steps[p];
        if visited > LOOK_AHEAD || !visit(p, step) {
            return false;
        }
        let then = r | bits(&step.restarts);
        match step.statement {
            Statement::Wait { test } => {
                if !false_now(&test, r) {
                    todo.push((p + 1, then));
                }
            }
            Statement::Branch { test, target } => {
                todo.push((p + 1, r));
                if target > p && !false_now(&test, r) {
                    todo.push((target, then));
                }
            }
            Statement::Act { ends_scan, .. } => {
                if !ends_scan {
                    todo.push((p + 1, then));
                }
            }
            Statement::Jump { target } => {
                if target > p {
                    todo.push((target, then));
                }
            }
        }
    }
    true
}

/// Whether the rest of the scan after request `i` (to `output`, with `mine`) might depend on
/// it, as [`chain_requests`] says; also when the scan could run on further than it looks.
fn scan_depends_on(code: &Code, facts: &[Option<RequestFacts>], i: usize, output: usize, mine: &RequestFacts) -> bool {
    let reads_feedback = |test: &Test| matches!(*test, Test::Input { input, .. } if mine.feedback.contains(&input));
    let independent = walk_scan(code, i + 1, &code.steps[i].restarts, |p, step| match step.statement {
        Statement::Wait { test } | Statement::Branch { test, .. } => !reads_feedback(&test),
        Statement::Act { output: other, .. } => {
            let commutes = facts
                .get(p)
                .and_then(Option::as_ref)
                .is_some_and(|f| !f.footprint.iter().any(|t| mine.footprint.contains(t)));
            other != output && commutes
        }
        Statement::Jump { .. } => true,
    });
    !independent
}

#[cfg(test)]
mod tests {
    use super::*;

    fn act(output: usize) -> Statement {
        Statement::Act { output, effect: Effect::Pulse, ends_scan: true }
    }

    fn input(input: usize) -> Test {
        Test::Input { input, negated: false }
    }

    /// Inputs `a_done`, `b_done`; outputs `a`, `b`; one timer restarted by `a`.
    fn code(steps: Vec<Step>) -> Code {
        let output = |s: &str| Output { variable: Variable::unbound(s), pulsed: true, last: Some(format!("last_{s}")) };
        Code {
            name: "fb".into(),
            program: "main".into(),
            instance: "ctrl".into(),
            gvl: "GVL_IO".into(),
            header: Vec::new(),
            inputs: vec![Variable::unbound("a_done"), Variable::unbound("b_done")],
            outputs: vec![output("a"), output("b")],
            timers: vec![Timer { symbol: "t".into(), comment: String::new(), preset_ms: 50 }],
            steps,
        }
    }

    fn facts(code: &Code, of: impl Fn(usize) -> RequestFacts) -> Vec<Option<RequestFacts>> {
        code.steps
            .iter()
            .map(|s| match s.statement {
                Statement::Act { output, .. } => Some(of(output)),
                _ => None,
            })
            .collect()
    }

    /// Output k's request: feedback on input k, its own machine as footprint (or a shared one).
    fn independent(k: usize) -> RequestFacts {
        RequestFacts { feedback: vec![k], footprint: vec![k as u32] }
    }

    fn ends(code: &Code) -> Vec<bool> {
        code.steps
            .iter()
            .filter_map(|s| match s.statement {
                Statement::Act { ends_scan, .. } => Some(ends_scan),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn independent_requests_share_a_scan_and_feedback_ends_it() {
        // DO a; DO b; WAIT a_done; WAIT b_done; GOTO 0: `a` goes on (b commutes with it, and
        // the scan cannot read a_done before b ends it), `b` ends the scan (a_done is not its
        // feedback, but b_done, read after it, is).
        let steps = vec![
            Step::new(act(0), vec![]),
            Step::new(act(1), vec![]),
            Step::new(Statement::Wait { test: input(0) }, vec![]),
            Step::new(Statement::Wait { test: input(1) }, vec![]),
            Step::new(Statement::Jump { target: 0 }, vec![]),
        ];
        let mut c = code(steps);
        let f = facts(&c, independent);
        chain_requests(&mut c, &f);
        assert_eq!(ends(&c), vec![false, true]);
        // DO a; DO b; WAIT a_done: b goes on (nothing reads b_done), so a_done is read in the
        // scan of `a`, which must end it.
        let mut c = code(c.steps[..3].to_vec());
        let f = facts(&c, independent);
        chain_requests(&mut c, &f);
        assert_eq!(ends(&c), vec![true, false]);
        // Requests that do not commute (a rule over both machines) never share a scan.
        let mut c = code(c.steps[..2].to_vec());
        let shared = facts(&c, |k| RequestFacts { feedback: vec![k], footprint: vec![k as u32, 7] });
        chain_requests(&mut c, &shared);
        assert_eq!(ends(&c), vec![true, false]);
        let f = facts(&c, independent);
        chain_requests(&mut c, &f);
        assert_eq!(ends(&c), vec![false, false]);
    }

    #[test]
    fn the_same_output_twice_or_an_unknown_request_ends_the_scan() {
        let steps = vec![
            Step::new(act(0), vec![]),
            Step::new(act(0), vec![]),
            Step::new(Statement::Jump { target: 0 }, vec![]),
        ];
        let mut c = code(steps);
        let f = facts(&c, independent);
        chain_requests(&mut c, &f);
        // The second `a` goes on into the backward jump, which ends the scan; the first may not
        // meet it in the same scan.
        assert_eq!(ends(&c), vec![true, false]);
        let mut c = code(vec![Step::new(act(0), vec![]), Step::new(act(1), vec![])]);
        chain_requests(&mut c, &[Some(independent(0)), None]);
        assert_eq!(ends(&c), vec![true, true], "a request without facts is not known to commute");
    }

    #[test]
    fn a_timer_the_request_restarts_cuts_the_scan_short() {
        // DO a (restarts t); WAIT t >= 30 ms; IF b_done ...: the wait cannot pass in the scan
        // of the restart, so reading b_done behind it does not matter even if it were feedback.
        let elapsed = Test::Elapsed { timer: 0, ms: 30, strict: false };
        let steps = vec![
            Step::new(act(0), vec![0]),
            Step::new(Statement::Wait { test: elapsed }, vec![]),
            Step::new(Statement::Wait { test: input(0) }, vec![]),
        ];
        let mut c = code(steps);
        let f = facts(&c, independent);
        chain_requests(&mut c, &f);
        assert_eq!(ends(&c), vec![false]);
        // Without the restart the wait may pass and a_done is read: the scan ends.
        c.steps[0].restarts.clear();
        chain_requests(&mut c, &f);
        assert_eq!(ends(&c), vec![true]);
    }

    fn backs(code: &Code) -> Vec<usize> {
        (0..code.steps.len()).filter(|&i| code.steps[i].back_in_scan).collect()
    }

    #[test]
    fn a_backward_jump_goes_on_only_where_the_scan_cannot_loop() {
        // 0: WAIT a_done; 1: DO a (restarts t); 2: WAIT t >= 30 ms; 3: IF b_done THEN GOTO 0;
        // 4: GOTO 2. The branch back to 0 goes on (from 0 the scan ends at the timer wait, the
        // request's restart makes it false); the polling jump back to 2 may not (from 2 the
        // scan may come back to 2).
        let elapsed = Test::Elapsed { timer: 0, ms: 30, strict: false };
        let steps = vec![
            Step::new(Statement::Wait { test: input(0) }, vec![]),
            Step::new(act(0), vec![0]),
            Step::new(Statement::Wait { test: elapsed }, vec![]),
            Step::new(Statement::Branch { test: input(1), target: 0 }, vec![]),
            Step::new(Statement::Jump { target: 2 }, vec![]),
        ];
        let mut c = code(steps);
        let f = facts(&c, independent);
        chain_requests(&mut c, &f);
        assert_eq!(ends(&c), vec![false]);
        assert_eq!(backs(&c), vec![3]);
        // 0: WAIT b_done; 1: DO a (restarts t); 2: WAIT t >= 30 ms; 3: DO b; 4: GOTO 0. From 0
        // the scan cannot loop, but `b` goes on into the jump: its decision assumed the scan
        // ends there, so the jump must end it. With `b` ending its scan, the jump goes on.
        let steps = vec![
            Step::new(Statement::Wait { test: input(1) }, vec![]),
            Step::new(act(0), vec![0]),
            Step::new(Statement::Wait { test: elapsed }, vec![]),
            Step::new(act(1), vec![]),
            Step::new(Statement::Jump { target: 0 }, vec![]),
        ];
        let mut c = code(steps);
        let f = facts(&c, independent);
        chain_requests(&mut c, &f);
        assert_eq!(ends(&c), vec![false, false]);
        assert_eq!(backs(&c), Vec::<usize>::new(), "the jump is in the scan of `b`");
        let mut f = f;
        f[3] = None;
        chain_requests(&mut c, &f);
        assert_eq!(ends(&c), vec![false, true]);
        assert_eq!(backs(&c), vec![4]);
    }

    #[test]
    fn resume_at_follows_bare_jumps_only() {
        let steps = vec![
            Step::new(Statement::Wait { test: input(0) }, vec![]),
            Step::new(Statement::Jump { target: 3 }, vec![]),
            Step::new(Statement::Jump { target: 0 }, vec![0]),
            Step::new(Statement::Jump { target: 2 }, vec![]),
        ];
        let c = code(steps);
        assert_eq!(c.resume_at(1), 2, "through 1 and 3 to the jump with a restart");
        assert_eq!(c.resume_at(0), 0);
        assert_eq!(c.resume_at(4), 0, "past the end: the start");
    }
}
