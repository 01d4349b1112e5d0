//! The PLC targets: their names, labels, file extensions and time limits. The one list
//! [`Target::ALL`] is what the CLI, the page and the tests iterate.

use std::fmt;
use std::str::FromStr;

/// The output formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Target {
    /// IEC 61131-3 Structured Text: the function block and a program with `AT` mapping.
    St,
    /// TwinCAT 3: `.TcPOU` files for the block and the program, a `.TcGVL` for the I/O.
    Twincat,
    /// CODESYS V3 Structured Text: a global variable list with `AT` mapping and
    /// `{attribute 'qualified_only'}`, the block and a program using the list.
    Codesys,
    /// Siemens SCL for S7-300/400 (TIA Portal external source, standard access, `TON`).
    Scl,
    /// Siemens SCL for S7-1200/1500 (optimised access, `TON_TIME`).
    Scl1500,
    /// IEC 61131-3 Instruction List.
    Il,
    /// Siemens S7 Statement List (AWL), as in the thesis.
    Stl,
    /// PLCopen TC6 XML v2.01: the block, a program and a configuration with a task.
    Plcopen,
    /// ABB Automation Builder (AC500): PLCopen TC6 XML in the conventions of Eclipse ESCET's
    /// PLC generator for ABB: no named constants (their values written in place), the I/O as the
    /// configuration's global variables, the task interval as an ISO 8601 duration.
    Abb,
}

impl Target {
    /// Every target, in the order menus and help list them.
    pub const ALL: [Target; 9] = [
        Target::St,
        Target::Twincat,
        Target::Codesys,
        Target::Scl,
        Target::Scl1500,
        Target::Il,
        Target::Stl,
        Target::Plcopen,
        Target::Abb,
    ];

    /// The one table of names, labels and file extensions that the CLI, the page and the
    /// tests read.
    const fn describe(self) -> TargetInfo {
        let (name, label, extension) = match self {
            Target::St => ("st", "Structured Text (IEC 61131-3)", "st"),
            Target::Twincat => ("twincat", "TwinCAT 3 (.TcPOU, .TcGVL files)", "TcPOU"),
            Target::Codesys => ("codesys", "CODESYS V3 ST (GVL, block, program)", "st"),
            Target::Scl => ("scl", "SCL (Siemens S7-300/400)", "scl"),
            Target::Scl1500 => ("scl-1500", "SCL (Siemens S7-1200/1500, optimised)", "scl"),
            Target::Il => ("il", "Instruction List (IEC 61131-3)", "il"),
            Target::Stl => ("stl", "S7 STL / AWL", "awl"),
            Target::Plcopen => ("plcopen", "PLCopen TC6 XML", "xml"),
            Target::Abb => ("abb", "ABB Automation Builder (PLCopen XML)", "xml"),
        };
        TargetInfo { name, label, extension }
    }

    /// The name on the command line, in share links and in diagnostics (`st`, `plcopen`).
    pub const fn name(self) -> &'static str {
        self.describe().name
    }

    /// A label for people (`Structured Text (IEC 61131-3)`).
    pub const fn label(self) -> &'static str {
        self.describe().label
    }

    /// File extension of the main file, without the dot.
    pub const fn extension(self) -> &'static str {
        self.describe().extension
    }

    /// Whether the target writes several files (`compile -o` then names a directory).
    pub const fn multi_file(self) -> bool {
        matches!(self, Target::Twincat)
    }

    /// Whether the target's language writes Siemens tag names in quotes (`"Lamp On"`); the
    /// others accept only identifiers as symbols.
    pub const fn quotes_tags(self) -> bool {
        matches!(self, Target::Scl | Target::Scl1500 | Target::Stl)
    }

    /// The type in which this target writes delay thresholds and timer presets, and so the
    /// limits of its constants.
    pub fn time_type(self) -> TimeType {
        match self {
            // IEC 61131-3 leaves TIME's range to the implementation; 32-bit signed milliseconds
            // is the common one (and S7's TIME). PLCopen XML carries the IEC text; ABB's AC500
            // tools are CODESYS-based (unsigned milliseconds), the signed range fits both.
            Target::St | Target::Il | Target::Plcopen | Target::Abb => {
                TimeType::Millis { name: "IEC TIME", max_ms: i32::MAX as u64 }
            }
            Target::Scl | Target::Scl1500 => TimeType::Millis { name: "S7 TIME", max_ms: i32::MAX as u64 },
            // CODESYS and TwinCAT document TIME as an unsigned 32-bit count of milliseconds.
            Target::Codesys | Target::Twincat => {
                TimeType::Millis { name: "CODESYS/TwinCAT TIME", max_ms: u32::MAX as u64 }
            }
            Target::Stl => TimeType::S5Time,
        }
    }
}

/// Name, label and file extension of a target.
struct TargetInfo {
    name: &'static str,
    label: &'static str,
    extension: &'static str,
}

impl fmt::Display for Target {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A target name that is not one of [`Target::ALL`].
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct UnknownTarget(pub String);

impl fmt::Display for UnknownTarget {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let names: Vec<&str> = Target::ALL.iter().map(|t| t.name()).collect();
        write!(f, "unknown target `{}` (expected one of {})", self.0, names.join(", "))
    }
}

impl std::error::Error for UnknownTarget {}

impl FromStr for Target {
    type Err = UnknownTarget;

    fn from_str(name: &str) -> Result<Target, UnknownTarget> {
        Target::ALL.into_iter().find(|t| t.name() == name).ok_or_else(|| UnknownTarget(name.to_string()))
    }
}

/// How a target writes durations: the one place that knows the limits of each target's timers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimeType {
    /// `T#…MS`, a millisecond count of at most `max_ms`. A clock is one `TON` whose preset lies
    /// one time unit above its largest threshold, so that `ET > threshold` can become true.
    Millis { name: &'static str, max_ms: u64 },
    /// S7 `S5TIME` (`S5T#…`): three decimal digits times a base of 10 ms, 100 ms, 1 s or 10 s,
    /// so at most 2h46m30s. One S7 timer per threshold, preset to the threshold itself.
    S5Time,
}

/// The bases of S5TIME, in milliseconds, finest first.
const S5TIME_BASES_MS: [u128; 4] = [10, 100, 1000, 10_000];
/// The largest S5TIME: 999 × 10 s.
pub const S5TIME_MAX_MS: u64 = 9_990_000;

impl TimeType {
    /// The value a timer that signals "elapsed" (S5TIME's done bit) must be preset to for a test
    /// `ET ≥ ms`, or `ET > ms` when `strict`. Millisecond types compare `ET` directly and keep
    /// `ms`; an S5TIME timer counts in steps of its base, so "more than `ms`" is the smallest
    /// S5TIME value above `ms` (at most one base step later; never at `ms` itself, which a strict
    /// bound excludes). Above the S5TIME range it returns a value `refusal` refuses.
    pub fn preset_for(self, ms: u128, strict: bool) -> u128 {
        match self {
            TimeType::S5Time if strict => S5TIME_BASES_MS
                .into_iter()
                .map(|base| (ms / base + 1) * base)
                .find(|&above| above <= u128::from(S5TIME_MAX_MS) && self.refusal(above).is_none())
                .unwrap_or(u128::from(S5TIME_MAX_MS) + 1),
            _ => ms,
        }
    }

    /// Why `ms` cannot be written exactly (`None` if it can): a clause after "time constant …"
    /// and notes.
    pub(crate) fn refusal(self, ms: u128) -> Option<(String, Vec<String>)> {
        match self {
            TimeType::Millis { name, max_ms } => (ms > u128::from(max_ms))
                .then(|| (format!("exceeds {name} (at most {max_ms} ms = {})", human_duration(max_ms)), Vec::new())),
            TimeType::S5Time if ms > u128::from(S5TIME_MAX_MS) => Some((
                format!("exceeds S5TIME (at most {S5TIME_MAX_MS} ms = {})", human_duration(S5TIME_MAX_MS)),
                Vec::new(),
            )),
            TimeType::S5Time => {
                // The finest base that reaches `ms`: the one an assembler chooses (awlsim then
                // truncates to it).
                let base = S5TIME_BASES_MS.into_iter().find(|b| ms <= 999 * b).unwrap_or(10_000);
                (ms % base != 0).then(|| {
                    (
                        "is not exactly representable in S5TIME".to_string(),
                        vec![format!(
                            "S5TIME holds 3 decimal digits in steps of 10 ms, 100 ms, 1 s or 10 s; in steps of {base} ms \
                             it would become {} ms",
                            ms / base * base
                        )],
                    )
                })
            }
        }
    }

    /// The preset of the timer of a clock whose largest threshold is `largest_ms`.
    pub(crate) fn preset_ms(self, largest_ms: u128, unit_ms: u128) -> u128 {
        match self {
            TimeType::Millis { .. } => largest_ms + unit_ms,
            TimeType::S5Time => largest_ms,
        }
    }
}

/// A duration for people: `24d20h31m23s647ms`, `2h46m30s`, `0ms`.
pub(crate) fn human_duration(ms: u64) -> String {
    let parts = [
        (ms / 86_400_000, "d"),
        (ms / 3_600_000 % 24, "h"),
        (ms / 60_000 % 60, "m"),
        (ms / 1000 % 60, "s"),
        (ms % 1000, "ms"),
    ];
    let text: String = parts.iter().filter(|(v, _)| *v > 0).map(|(v, u)| format!("{v}{u}")).collect();
    if text.is_empty() {
        "0ms".to_string()
    } else {
        text
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_back_to_their_target() {
        for target in Target::ALL {
            assert_eq!(target.name().parse(), Ok(target));
            assert_eq!(target.to_string(), target.name());
        }
        assert_eq!("ST".parse::<Target>(), Err(UnknownTarget("ST".to_string())));
    }

    #[test]
    fn a_strict_s5time_threshold_waits_for_the_next_value() {
        let s5 = TimeType::S5Time;
        assert_eq!(s5.preset_for(2000, false), 2000);
        assert_eq!(s5.preset_for(2000, true), 2010);
        assert_eq!(s5.preset_for(0, true), 10);
        // 9 990 ms is 999 steps of 10 ms; the next value needs the 100 ms base.
        assert_eq!(s5.preset_for(9990, true), 10_000);
        assert_eq!(s5.preset_for(1_000_000, true), 1_010_000);
        assert!(s5.refusal(s5.preset_for(u128::from(S5TIME_MAX_MS), true)).is_some());
        assert_eq!(TimeType::Millis { name: "IEC TIME", max_ms: 10 }.preset_for(5, true), 5);
    }

    #[test]
    fn s5time_holds_three_digits_in_one_of_four_steps() {
        let holds = |ms: u128| TimeType::S5Time.refusal(ms).is_none();
        for ms in [0, 10, 9990, 10_000, 99_900, 100_000, 999_000, 1_000_000, 9_990_000] {
            assert!(holds(ms), "{ms}");
        }
        for ms in [1, 5, 9995, 10_010, 99_950, 100_100, 999_100, 1_000_100, 9_990_010, 10_000_000] {
            assert!(!holds(ms), "{ms}");
        }
    }

    #[test]
    fn millisecond_types_hold_up_to_their_maximum() {
        let time = Target::St.time_type();
        assert!(time.refusal(2_147_483_647).is_none());
        assert!(time.refusal(2_147_483_648).is_some());
        assert_eq!(human_duration(2_147_483_647), "24d20h31m23s647ms");
        assert_eq!(human_duration(S5TIME_MAX_MS), "2h46m30s");
        assert_eq!(human_duration(0), "0ms");
    }
}
