//! Import and export of libFAUDES `.gen` generator files.
//!
//! The reader accepts the token format libFAUDES writes and reads: `%` comments, markup tags
//! `<Section ...>`/`</Section>`, quoted or bare names, integer state indices, `name#index`
//! state names, `<Consecutive> a b </Consecutive>` index ranges in `<States>`, and event
//! attributes such as `+C+` (controllable) after an event in `<Alphabet>`. Unknown sections are
//! skipped. The writer emits quoted names so that any name round-trips.

use super::classic::{Automaton, AutomatonBuilder, Events, StateId};
use hashbrown::HashMap;
use std::fmt::Write as _;

/// A located error in a `.gen` text.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct GenError {
    /// Byte offset of the offending token.
    pub offset: usize,
    pub message: String,
}

#[derive(Clone, Debug, PartialEq, Eq)]
enum Tok {
    Begin(String),
    End(String),
    Str(String),
    Word(String),
}

fn tokenize(src: &str) -> Result<Vec<(usize, Tok)>, GenError> {
    let b = src.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < b.len() {
        let c = b[i];
        if c.is_ascii_whitespace() {
            i += 1;
        } else if c == b'%' {
            while i < b.len() && b[i] != b'\n' {
                i += 1;
            }
        } else if c == b'<' {
            let start = i;
            let Some(len) = src[i..].find('>') else {
                return Err(GenError { offset: start, message: "unterminated markup tag".into() });
            };
            let inner = &src[i + 1..i + len];
            i += len + 1;
            let (end, rest) = match inner.strip_prefix('/') {
                Some(r) => (true, r),
                None => (false, inner),
            };
            let name = rest.split_whitespace().next().unwrap_or("").trim_end_matches('/').to_string();
            if name.is_empty() {
                return Err(GenError { offset: start, message: "empty markup tag".into() });
            }
            out.push((start, if end { Tok::End(name) } else { Tok::Begin(name) }));
        } else if c == b'"' {
            let start = i;
            i += 1;
            let s = i;
            while i < b.len() && b[i] != b'"' {
                i += 1;
            }
            if i >= b.len() {
                return Err(GenError { offset: start, message: "unterminated string".into() });
            }
            out.push((start, Tok::Str(src[s..i].to_string())));
            i += 1;
        } else {
            let start = i;
            while i < b.len() && !b[i].is_ascii_whitespace() && b[i] != b'<' && b[i] != b'"' {
                i += 1;
            }
            out.push((start, Tok::Word(src[start..i].to_string())));
        }
    }
    Ok(out)
}

/// A state reference as written in a section: an index or a name.
enum StateRef {
    Index(u64),
    Name(String),
}

fn state_ref(t: &Tok) -> Option<StateRef> {
    match t {
        Tok::Str(s) => Some(StateRef::Name(s.clone())),
        Tok::Word(w) => {
            if let Ok(i) = w.parse::<u64>() {
                Some(StateRef::Index(i))
            } else if let Some((name, idx)) = w.split_once('#') {
                if idx.parse::<u64>().is_ok() && !name.is_empty() {
                    Some(StateRef::Name(name.to_string()))
                } else {
                    Some(StateRef::Name(w.clone()))
                }
            } else {
                Some(StateRef::Name(w.clone()))
            }
        }
        _ => None,
    }
}

/// Reads a generator, adding its events to `events` (controllability from `+C+` attributes;
/// an event already known keeps being controllable if either source says so).
pub fn read_gen(src: &str, events: &mut Events) -> Result<Automaton, GenError> {
    let toks = tokenize(src)?;
    let mut pos = 0;
    let err = |off: usize, m: &str| GenError { offset: off, message: m.to_string() };
    // Find <Generator>.
    while pos < toks.len() && toks[pos].1 != Tok::Begin("Generator".into()) {
        pos += 1;
    }
    if pos == toks.len() {
        return Err(err(0, "no <Generator> section"));
    }
    pos += 1;
    if let Some((_, Tok::Str(_))) = toks.get(pos) {
        pos += 1; // generator name
    }
    let mut b = AutomatonBuilder::new();
    let mut by_name: HashMap<String, StateId> = HashMap::new();
    let mut by_index: HashMap<u64, StateId> = HashMap::new();
    let mut next_index: u64 = 1;
    let mut alphabet_events = Vec::new();
    let mut init = Vec::new();
    let mut marked = Vec::new();
    let mut trans = Vec::new();
    let mut seen_states = false;
    loop {
        let Some((off, t)) = toks.get(pos) else { return Err(err(src.len(), "missing </Generator>")) };
        pos += 1;
        let section = match t {
            Tok::End(n) if n == "Generator" => break,
            Tok::Begin(n) => n.clone(),
            _ => return Err(err(*off, "expected a section tag")),
        };
        // Collect the tokens up to the matching end tag.
        let start = pos;
        let mut depth = 0;
        while pos < toks.len() {
            match &toks[pos].1 {
                Tok::Begin(n) if *n == section => depth += 1,
                Tok::End(n) if *n == section => {
                    if depth == 0 {
                        break;
                    }
                    depth -= 1;
                }
                _ => {}
            }
            pos += 1;
        }
        if pos >= toks.len() {
            return Err(err(*off, &format!("missing </{section}>")));
        }
        let body = &toks[start..pos];
        pos += 1;
        match section.as_str() {
            "Alphabet" => {
                let mut last: Option<usize> = None;
                for (o, t) in body {
                    match t {
                        Tok::Word(w) if w.len() >= 2 && w.starts_with('+') && w.ends_with('+') => {
                            let Some(i) = last else { return Err(err(*o, "attribute before any event")) };
                            if w.contains('C') {
                                let e = alphabet_events[i];
                                events.set_controllable(e, true);
                            }
                        }
                        Tok::Word(w) | Tok::Str(w) => {
                            let e = events.intern(w, false);
                            alphabet_events.push(e);
                            last = Some(alphabet_events.len() - 1);
                        }
                        _ => return Err(err(*o, "unexpected markup in <Alphabet>")),
                    }
                }
            }
            "States" => {
                seen_states = true;
                let mut i = 0;
                while i < body.len() {
                    let (o, t) = &body[i];
                    match t {
                        Tok::Begin(n) if n == "Consecutive" => {
                            let (Some((_, Tok::Word(a))), Some((_, Tok::Word(z))), Some((_, Tok::End(_)))) =
                                (body.get(i + 1), body.get(i + 2), body.get(i + 3))
                            else {
                                return Err(err(*o, "malformed <Consecutive> range"));
                            };
                            let (Ok(a), Ok(z)) = (a.parse::<u64>(), z.parse::<u64>()) else {
                                return Err(err(*o, "malformed <Consecutive> range"));
                            };
                            if z < a || z - a > 10_000_000 {
                                return Err(err(*o, "malformed <Consecutive> range"));
                            }
                            for k in a..=z {
                                let s = b.add_state(k.to_string(), false);
                                by_index.insert(k, s);
                            }
                            next_index = z + 1;
                            i += 4;
                            continue;
                        }
                        _ => match state_ref(t) {
                            Some(StateRef::Index(k)) => {
                                if by_index.contains_key(&k) {
                                    return Err(err(*o, "duplicate state index"));
                                }
                                let s = b.add_state(k.to_string(), false);
                                by_index.insert(k, s);
                                next_index = next_index.max(k + 1);
                            }
                            Some(StateRef::Name(nm)) => {
                                if by_name.contains_key(&nm) {
                                    return Err(err(*o, &format!("duplicate state `{nm}`")));
                                }
                                let s = b.add_state(nm.clone(), false);
                                by_name.insert(nm, s);
                                by_index.insert(next_index, s);
                                next_index += 1;
                            }
                            None => return Err(err(*o, "unexpected markup in <States>")),
                        },
                    }
                    i += 1;
                }
            }
            "TransRel" | "InitStates" | "MarkedStates" => {
                let mut refs = Vec::new();
                for (o, t) in body {
                    refs.push((*o, t.clone()));
                }
                match section.as_str() {
                    "TransRel" => trans = refs,
                    "InitStates" => init = refs,
                    _ => marked = refs,
                }
            }
            _ => {} // other sections (attributes, names) are ignored
        }
    }
    if !seen_states {
        return Err(err(0, "missing <States> section"));
    }
    let lookup = |o: usize, t: &Tok| -> Result<StateId, GenError> {
        match state_ref(t) {
            Some(StateRef::Index(k)) => {
                by_index.get(&k).copied().ok_or_else(|| err(o, &format!("unknown state index {k}")))
            }
            Some(StateRef::Name(n)) => by_name.get(&n).copied().ok_or_else(|| err(o, &format!("unknown state `{n}`"))),
            None => Err(err(o, "expected a state")),
        }
    };
    for &e in &alphabet_events {
        b.add_event(e);
    }
    if trans.len() % 3 != 0 {
        return Err(err(trans.last().map_or(0, |t| t.0), "transitions come in triples: source event target"));
    }
    for c in trans.chunks(3) {
        let s = lookup(c[0].0, &c[0].1)?;
        let ename = match &c[1].1 {
            Tok::Word(w) | Tok::Str(w) => w,
            _ => return Err(err(c[1].0, "expected an event")),
        };
        let Some(e) = events.get(ename).filter(|e| alphabet_events.contains(e)) else {
            return Err(err(c[1].0, &format!("event `{ename}` is not in the alphabet")));
        };
        let t = lookup(c[2].0, &c[2].1)?;
        b.add_transition(s, e, t);
    }
    let inits: Vec<StateId> = init.iter().map(|(o, t)| lookup(*o, t)).collect::<Result<_, _>>()?;
    if inits.len() > 1 {
        return Err(err(init[1].0, "more than one initial state (nondeterministic generator)"));
    }
    for (o, t) in &marked {
        let s = lookup(*o, t)?;
        b.set_marked(s, true);
    }
    if let Some(&i) = inits.first() {
        b.set_init(i);
    }
    b.build().map_err(|e| err(0, &format!("invalid generator: {e:?}")))
}

fn quote(s: &str) -> String {
    // libFAUDES strings cannot contain quotes; replace them.
    format!("\"{}\"", s.replace('"', "'"))
}

/// Writes a generator in libFAUDES format; controllable events carry `+C+`.
pub fn write_gen(a: &Automaton, events: &Events, name: &str) -> String {
    let mut o = String::new();
    let _ = writeln!(o, "<Generator>\n{}\n<Alphabet>", quote(name));
    for &e in a.alphabet() {
        let _ = writeln!(o, "{}{}", quote(events.name(e)), if events.is_controllable(e) { " +C+" } else { "" });
    }
    o.push_str("</Alphabet>\n<States>\n");
    // State names: s<id> keeps them unique regardless of the original names.
    for s in 0..a.num_states() {
        let _ = writeln!(o, "\"s{s}\"");
    }
    o.push_str("</States>\n<TransRel>\n");
    for s in 0..a.num_states() as StateId {
        for e in a.edges(s) {
            let _ = writeln!(o, "\"s{s}\" {} \"s{}\"", quote(events.name(e.event)), e.target);
        }
    }
    o.push_str("</TransRel>\n<InitStates>\n");
    if let Some(i) = a.init() {
        let _ = writeln!(o, "\"s{i}\"");
    }
    o.push_str("</InitStates>\n<MarkedStates>\n");
    for s in 0..a.num_states() as StateId {
        if a.is_marked(s) {
            let _ = writeln!(o, "\"s{s}\"");
        }
    }
    o.push_str("</MarkedStates>\n</Generator>\n");
    o
}

#[cfg(test)]
mod tests {
    use super::*;

    const FAUDES_STYLE: &str = r#"<Generator ftype="System">
% comment
<Alphabet>
x              c              +C+
</Alphabet>
<States>
<Consecutive> 1 2 </Consecutive> 4 named#8
</States>
<TransRel>
1 x 2
2 c named
</TransRel>
<InitStates> 1 </InitStates>
<MarkedStates> 2 </MarkedStates>
</Generator>"#;

    #[test]
    fn reads_faudes_written_syntax() {
        let mut ev = Events::new();
        let a = read_gen(FAUDES_STYLE, &mut ev).unwrap();
        assert_eq!(a.num_states(), 4);
        assert_eq!(a.num_transitions(), 2);
        assert!(ev.is_controllable(ev.get("c").unwrap()));
        assert!(!ev.is_controllable(ev.get("x").unwrap()));
        assert!(a.run(&[ev.get("x").unwrap(), ev.get("c").unwrap()]).is_some());
    }

    #[test]
    fn round_trips_through_writer() {
        let mut ev = Events::new();
        let a = read_gen(FAUDES_STYLE, &mut ev).unwrap();
        let text = write_gen(&a, &ev, "g");
        let mut ev2 = Events::new();
        let b = read_gen(&text, &mut ev2).unwrap();
        assert_eq!((b.num_states(), b.num_transitions()), (4, 2));
        assert!(ev2.is_controllable(ev2.get("c").unwrap()));
    }

    #[test]
    fn reports_unknown_event_with_offset() {
        let src = "<Generator> <Alphabet> a </Alphabet> <States> 1 </States> <TransRel> 1 b 1 </TransRel> </Generator>";
        let e = read_gen(src, &mut Events::new()).unwrap_err();
        assert_eq!(&src[e.offset..e.offset + 1], "b");
    }
}
