//! `plcsynth import` and `plcsynth export`: `.sct` projects from and to other tools' files
//! (Supremica `.wmod`, libFAUDES `.gen`), and the classic inputs of `supcon` read from either.

use clap::Args;
use plcsynth::diag::{render_plain, Diagnostics, Span};
use plcsynth::sct::classic::wmod::{decode, read_wmod_within, write_wmod, ComponentKind, ComponentOut, Module};
use plcsynth::sct::classic::{product_within, Automaton, Events};
use plcsynth::sct::interchange::{import as import_files, is_wmod, project_to_classic, Import, ImportFile, ToSct};
use plcsynth::sct::model::{Budget, Config, DEFAULT_MAX_STATES};
use plcsynth::sct::{compile_within, synthesize_within, Verdict};
use std::process::ExitCode;

#[derive(Args)]
pub struct ImportArgs {
    /// A Supremica module (`.wmod`), or libFAUDES generators (`.gen`) read as plants.
    #[arg(required = true)]
    pub files: Vec<String>,
    /// A libFAUDES generator (`.gen`) read as a specification (repeatable).
    #[arg(long, value_name = "FILE.gen")]
    pub spec: Vec<String>,
    /// Write the project here instead of standard output.
    #[arg(short, long)]
    pub output: Option<String>,
    /// Read every state as marked instead of refusing unmarked states (`.sct` has no marking).
    #[arg(long)]
    pub ignore_marking: bool,
    /// State budget: the states the input files may declare in all; past it, exit status 3.
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_STATES)]
    pub max_states: usize,
}

#[derive(Args)]
pub struct ExportArgs {
    /// The `.sct` project.
    pub file: String,
    /// Write the module here (`.wmod`) instead of standard output.
    #[arg(short, long)]
    pub output: Option<String>,
    /// Also synthesise the supervisors (incremental, with preemption, minimised) and write them
    /// as SUPERVISOR components.
    #[arg(long)]
    pub with_supervisors: bool,
    /// State budget of the synthesis (as `supervise --max-states`).
    #[arg(long, value_name = "N", default_value_t = DEFAULT_MAX_STATES)]
    pub max_states: usize,
}

/// Reads a file as text; a `.wmod` may be in Supremica's `windows-1252`.
pub(crate) fn read_text(path: &str) -> Result<String, ExitCode> {
    let bytes = std::fs::read(path).map_err(|e| {
        eprintln!("error: cannot read `{path}`: {e}");
        ExitCode::from(2)
    })?;
    match decode(&bytes) {
        Some(text) => Ok(text.into_owned()),
        None => {
            eprintln!("error: `{path}` is not UTF-8 text (and declares no windows-1252 or ISO-8859-1 encoding)");
            Err(ExitCode::from(2))
        }
    }
}

/// Writes `text` to `output`, or to standard output.
fn write_out(output: Option<&str>, text: &str) -> ExitCode {
    match output {
        Some(path) => match std::fs::write(path, text) {
            Ok(()) => ExitCode::SUCCESS,
            Err(e) => {
                eprintln!("error: cannot write `{path}`: {e}");
                ExitCode::from(1)
            }
        },
        None => {
            use std::io::Write as _;
            let _ = std::io::stdout().write_all(text.as_bytes());
            ExitCode::SUCCESS
        }
    }
}

/// Reads a `.wmod` file within the budget; errors rendered, exit code 2 or 3.
pub(crate) fn read_module(path: &str, events: &mut Events, max_states: usize) -> Result<(String, Module), ExitCode> {
    let src = read_text(path)?;
    match read_wmod_within(&src, events, max_states) {
        Ok(m) => Ok((src, m)),
        Err(e) => {
            eprint!("{}", render_plain(path, &src, &[e.diagnostic(&src)]));
            Err(ExitCode::from(if e.over_budget { 3 } else { 2 }))
        }
    }
}

pub fn import(a: &ImportArgs) -> ExitCode {
    let wmods = a.files.iter().filter(|f| is_wmod(f)).count();
    if wmods > 0 && (a.files.len() > 1 || !a.spec.is_empty()) {
        eprintln!("error: import one `.wmod` module at a time, without other files");
        return ExitCode::from(2);
    }
    let paths: Vec<(&String, ComponentKind)> = a
        .files
        .iter()
        .map(|f| (f, ComponentKind::Plant))
        .chain(a.spec.iter().map(|f| (f, ComponentKind::Spec)))
        .collect();
    let mut texts = Vec::new();
    for (path, _) in &paths {
        match read_text(path) {
            Ok(text) => texts.push(text),
            Err(c) => return c,
        }
    }
    let files: Vec<ImportFile> =
        paths.iter().zip(&texts).map(|((name, kind), text)| ImportFile { name, text, kind: *kind }).collect();
    let options = Import {
        by: "`plcsynth import`",
        to_sct: ToSct { ignore_marking: a.ignore_marking, ..ToSct::default() },
        max_states: a.max_states,
    };
    match import_files(&files, &options) {
        Ok(text) => write_out(a.output.as_deref(), &text),
        Err(errors) => {
            for e in &errors {
                let f = &files[e.file];
                eprint!("{}", render_plain(f.name, f.text, std::slice::from_ref(&e.diagnostic)));
            }
            if errors.iter().any(|e| e.over_budget) {
                return ExitCode::from(3);
            }
            eprintln!("nothing written");
            ExitCode::from(2)
        }
    }
}

pub fn export(a: &ExportArgs) -> ExitCode {
    if let Some(o) = &a.output {
        if !is_wmod(o) {
            eprintln!("error: `plcsynth export` writes Supremica modules: name the output `….wmod`");
            return ExitCode::from(2);
        }
    }
    let src = match read_text(&a.file) {
        Ok(s) => s,
        Err(c) => return c,
    };
    let mut go_on = |_: &_| true;
    let mut budget = Budget::new(a.max_states, &mut go_on);
    let (loaded, diags, stop) = compile_within(&src, &mut budget);
    if !diags.is_empty() {
        eprint!("{}", render_plain(&a.file, &src, &diags));
    }
    if stop.is_some() {
        return ExitCode::from(3);
    }
    let Some(loaded) = loaded else { return ExitCode::from(2) };
    let mut reports = Vec::new();
    if a.with_supervisors {
        let cfg = Config { max_states: a.max_states, ..Config::default() };
        let synthesis = synthesize_within(&src, &loaded, &cfg, None, &mut budget);
        if !synthesis.diagnostics.is_empty() {
            eprint!("{}", render_plain(&a.file, &src, &synthesis.diagnostics));
        }
        match synthesis.outcome {
            Err(_) => return ExitCode::from(3),
            Ok(Verdict::Error) => return ExitCode::from(2),
            Ok(_) => reports = synthesis.reports,
        }
    }
    let sups: Vec<_> = reports.iter().map(|r| &r.supervisor).collect();
    write_project(&a.file, &src, &loaded, &sups, false, a.output.as_deref())
}

/// Writes a checked project's plants and specifications (unless `only_supervisors`) and `sups`
/// as a module; what is not written is said on standard error and in the module's comment.
pub(crate) fn write_project(
    file: &str,
    src: &str,
    loaded: &plcsynth::sct::Loaded,
    sups: &[&plcsynth::sct::model::Supervisor],
    only_supervisors: bool,
    output: Option<&str>,
) -> ExitCode {
    let classic = match project_to_classic(src, loaded, sups) {
        Ok(c) => c,
        Err(diags) => {
            eprint!("{}", render_plain(file, src, &diags));
            eprintln!("nothing written");
            return ExitCode::from(2);
        }
    };
    let name = std::path::Path::new(file).file_stem().and_then(|s| s.to_str()).unwrap_or("module");
    let mut comment = format!("Exported by plcsynth from {file}.");
    let mut left_out = classic.enforcement.clone();
    if !only_supervisors {
        left_out.extend(classic.left_out.iter().cloned());
    }
    if !left_out.is_empty() {
        comment.push_str("\nNot in this module (no Waters equivalent):");
        eprintln!("note: not written (no Waters equivalent):");
        for l in &left_out {
            comment.push_str("\n- ");
            comment.push_str(l);
            eprintln!("  - {l}");
        }
    }
    let out: Vec<ComponentOut> = classic
        .components
        .iter()
        .filter(|(_, kind, _)| !only_supervisors || *kind == ComponentKind::Supervisor)
        .map(|(name, kind, automaton)| ComponentOut { name, kind: *kind, automaton })
        .collect();
    write_out(output, &write_wmod(name, &comment, &out, &classic.events, &classic.attributes()))
}

/// The synchronous product of `parts` within `max_states`; `None` past it.
pub(crate) fn compose(parts: &[&Automaton], events: &Events, max_states: usize) -> Option<Automaton> {
    let mut it = parts.iter();
    let mut acc = (*it.next()?).clone();
    for p in it {
        acc = product_within(&acc, p, events.len(), max_states).ok()?.automaton;
    }
    Some(acc)
}

/// The plant (PLANT components) or specification (SPEC and SUPERVISOR components) of a module
/// for `supcon`, composed; a module without one is an error at its root element.
pub(crate) fn module_side(
    path: &str,
    src: &str,
    m: &Module,
    plant: bool,
    events: &Events,
    max_states: usize,
) -> Result<Automaton, ExitCode> {
    let wanted = |k: ComponentKind| {
        if plant {
            k == ComponentKind::Plant
        } else {
            matches!(k, ComponentKind::Spec | ComponentKind::Supervisor)
        }
    };
    let parts: Vec<&Automaton> = m.components.iter().filter(|c| wanted(c.kind)).map(|c| &c.automaton).collect();
    if plant {
        for c in m.components.iter().filter(|c| c.kind == ComponentKind::Property) {
            let mut d = Diagnostics::new(src);
            d.warning(c.span, format!("the property `{}` is not used: supcon reads plants and specifications", c.name));
            eprint!("{}", render_plain(path, src, &d.items));
        }
    }
    if parts.is_empty() {
        let mut d = Diagnostics::new(src);
        let at = src.find("<Module").or_else(|| src.find(":Module")).unwrap_or(0);
        let what = if plant { "PLANT" } else { "SPEC or SUPERVISOR" };
        d.error(Span::new(at, at + 7), format!("module `{}` has no {what} component", m.name));
        eprint!("{}", render_plain(path, src, &d.items));
        return Err(ExitCode::from(2));
    }
    match compose(&parts, events, max_states) {
        Some(a) => Ok(a),
        None => {
            eprintln!(
                "error: the {} components of `{path}` compose to more than {max_states} states",
                if plant { "plant" } else { "specification" }
            );
            eprintln!("note: the state budget is {max_states} states; raise it with --max-states N");
            Err(ExitCode::from(3))
        }
    }
}
