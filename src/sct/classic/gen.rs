//! Import and export of libFAUDES `.gen` generator files.
//!
//! A libFAUDES file is a token stream (libFAUDES `Token::Read`, `TokenReader`):
//! - `%` starts a comment to the end of the line; XML comments, `<?…?>` and `<!DOCTYPE …>` are
//!   skipped;
//! - markup: `<Section attr="v">` … `</Section>`, and `<Section/>`, the empty section, which
//!   libFAUDES writes for every empty set (`<TransRel/>`, `<MarkedStates/>`, `<Alphabet/>`, …);
//! - strings: bare words, `"quoted"` or `'quoted'` with the entities `&lt; &gt; &amp; &quot;
//!   &apos;`, and `<![CDATA[…]]>`; a bare word that libFAUDES reads as a number (`7`, `0x1F`,
//!   `1.5`, `true`, `inf`) is a number;
//! - options `+C+` and base64 data `=…=` (attributes).
//!
//! A generator (libFAUDES `vGenerator::DoRead`) comes in two formats, both read here:
//! - native (`Write`): an optional name, `<Alphabet>` (events, each optionally followed by
//!   attributes such as `+C+`), `<States>` (indices, names, `name#index`, `<Consecutive> a b
//!   </Consecutive>`), `<TransRel>` (triples), `<InitStates>`, `<MarkedStates>`; the short tags
//!   `<A> <S> <T> <I> <M>`; when `<States>` (or `<Alphabet>`) is empty, `<TransRel>` introduces
//!   the states (or events) it names, as libFAUDES 2.24e allows;
//! - XML (`XWrite`): `<Alphabet>` of `<Event name=…>` elements with `<Controllable/>`,
//!   `<StateSet>` of `<State id=… name=…>` with `<Initial/>`/`<Marked/>` and `<Consecutive
//!   from=… to=…/>`, `<TransitionRelation>` of `<Transition x1=… event=… x2=…/>`.
//!
//! Unnamed states get the next index (libFAUDES counts every state read so far); attributes
//! that are not controllability and sections libFAUDES would skip are skipped. The first
//! top-level `<Generator>` section is read (or the first top-level section, for a generator
//! written under another label). Every error is located; the generator must be deterministic.
//! The writer emits the native format with names quoted where libFAUDES would misread them.

use super::{Automaton, AutomatonBuilder, BuildError, ClassicEventId, Events, StateId};
use crate::diag::Span;
use hashbrown::{HashMap, HashSet};
use std::fmt::Write as _;

/// A located error in a `.gen` text.
pub type GenError = super::FileError;

/// More than `max_states` states declared, at `span`.
fn over_budget(span: Span, max_states: usize) -> GenError {
    GenError::budget(span, "the generator", max_states).note("a short `<Consecutive>` range can declare millions of states; raise the budget (`--max-states N`) if the file is meant to be this large")
}

/// A generator read from a `.gen` text, with where its events are named.
pub struct GenFile {
    pub automaton: Automaton,
    /// The first mention of each event of the alphabet (in `<Alphabet>`, or in `<TransRel>`
    /// when that introduces it).
    event_spans: HashMap<ClassicEventId, Span>,
}

impl GenFile {
    /// Where the file first names `e`, if it is in the generator's alphabet.
    pub fn event_span(&self, e: ClassicEventId) -> Option<Span> {
        self.event_spans.get(&e).copied()
    }
}

/// How libFAUDES reads a bare word (`Token::InterpretNumber`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Number {
    No,
    Integer(i64),
    /// `0x…`: libFAUDES's flag notation.
    Hex(i64),
    /// `true`, `false` (and their capitalised forms).
    Boolean(i64),
    /// Negative numbers (and libFAUDES's decimals with a sign).
    Float,
}

fn interpret_number(s: &str) -> Number {
    match s {
        "inf" | "+inf" => return Number::Integer(i64::MAX),
        "-inf" => return Number::Integer(i64::MIN + 1),
        "true" | "True" => return Number::Boolean(1),
        "false" | "False" => return Number::Boolean(0),
        _ => {}
    }
    let (mut value, mut base, mut comma, mut minus, mut ok) = (0i64, 10i64, -1i32, false, false);
    for (count, c) in s.bytes().enumerate() {
        if c == b'x' && value == 0 && count == 1 && comma < 0 && !minus {
            base = 16;
            continue;
        }
        if c == b'-' && count == 0 {
            minus = true;
            continue;
        }
        if c == b'.' && comma < 0 && base == 10 {
            comma = 0;
            continue;
        }
        let digit = match (c as char).to_digit(base as u32) {
            Some(d) => d as i64,
            None => return Number::No,
        };
        value = value.wrapping_mul(base).wrapping_add(digit);
        if comma >= 0 {
            comma += 1;
        }
        ok = true;
    }
    if !ok {
        return Number::No;
    }
    // libFAUDES drops the decimals and then counts the result as an integer: `1.5` reads as 1.
    if minus {
        Number::Float
    } else if base == 16 {
        Number::Hex(value)
    } else {
        let mut v = value;
        while comma > 0 {
            v /= 10;
            comma -= 1;
        }
        Number::Integer(v)
    }
}

#[derive(Clone, Debug, PartialEq, Eq)]
enum Kind {
    /// `<Tag attr="v">`; a self-closing `<Tag/>` is a `Begin` and an `End` at the same place.
    Begin {
        name: String,
        attrs: Vec<(String, String)>,
    },
    End(String),
    /// A bare word, a quoted string or CDATA; `number` is libFAUDES's reading of a bare word.
    Text {
        text: String,
        number: Number,
    },
    /// `+…+`: an attribute option such as `+C+`.
    Option(String),
    /// `=…=`: base64 data, an attribute of other libFAUDES types.
    Binary,
}

/// libFAUDES's token classes in the precedence of `Token::Type`, which decides what
/// `AttrType::Skip` passes over as an attribute.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Class {
    Begin,
    End,
    Hex,
    Boolean,
    Integer,
    Float,
    Option,
    Binary,
    String,
}

#[derive(Clone, Debug)]
struct Tok {
    kind: Kind,
    span: Span,
}

impl Tok {
    fn class(&self) -> Class {
        match &self.kind {
            Kind::Begin { .. } => Class::Begin,
            Kind::End(_) => Class::End,
            Kind::Text { number, .. } => match number {
                Number::No => Class::String,
                Number::Integer(_) => Class::Integer,
                Number::Hex(_) => Class::Hex,
                Number::Boolean(_) => Class::Boolean,
                Number::Float => Class::Float,
            },
            Kind::Option(_) => Class::Option,
            Kind::Binary => Class::Binary,
        }
    }

    /// The value where libFAUDES's `IsInteger` holds.
    fn integer(&self) -> Option<i64> {
        match &self.kind {
            Kind::Text { number: Number::Integer(v) | Number::Hex(v) | Number::Boolean(v), .. } => Some(*v),
            _ => None,
        }
    }

    /// A name: any bare word (numbers included, as libFAUDES's `IsString`) or quoted string.
    fn text(&self) -> Option<&str> {
        match &self.kind {
            Kind::Text { text, .. } => Some(text),
            _ => None,
        }
    }

    fn is_begin(&self, tag: &str) -> bool {
        matches!(&self.kind, Kind::Begin { name, .. } if name == tag)
    }

    fn attr(&self, key: &str) -> Option<&str> {
        match &self.kind {
            Kind::Begin { attrs, .. } => attrs.iter().find(|(k, _)| k == key).map(|(_, v)| v.as_str()),
            _ => None,
        }
    }

    /// The token as the user wrote it, for messages.
    fn describe(&self) -> String {
        match &self.kind {
            Kind::Begin { name, .. } => format!("<{name}>"),
            Kind::End(name) => format!("</{name}>"),
            Kind::Text { text, .. } => format!("`{text}`"),
            Kind::Option(o) => format!("`+{o}+`"),
            Kind::Binary => "binary data".into(),
        }
    }
}

/// Control characters and blanks separate tokens, as C's `iscntrl`/`isspace` in libFAUDES.
fn is_space(c: u8) -> bool {
    c <= b' ' || c == 0x7f
}

struct Lexer<'a> {
    src: &'a str,
    b: &'a [u8],
    i: usize,
}

impl<'a> Lexer<'a> {
    fn err(&self, start: usize, message: impl Into<String>) -> GenError {
        GenError::at(Span::new(start, (start + 1).min(self.b.len()).max(start)), message)
    }

    fn peek(&self) -> Option<u8> {
        self.b.get(self.i).copied()
    }

    /// Reads an escaped string up to `stop` (not consumed), as `Token::ReadEscapedString`: a bare
    /// word (`stop == None`) also ends at blanks and control characters; every string ends at
    /// markup. Runs of control characters in quoted strings become one blank.
    fn escaped(&mut self, stop: Option<u8>) -> String {
        let mut out = String::new();
        let mut start = self.i;
        let mut blank_run = false;
        while let Some(c) = self.peek() {
            if c == b'<' || c == b'>' || Some(c) == stop || (stop.is_none() && is_space(c)) {
                break;
            }
            if c == b'&' {
                out.push_str(&self.src[start..self.i]);
                let rest = &self.src[self.i..];
                let entity = [("&amp;", '&'), ("&quot;", '"'), ("&apos;", '\''), ("&lt;", '<'), ("&gt;", '>')]
                    .into_iter()
                    .find(|(e, _)| rest.starts_with(e));
                match entity {
                    Some((e, ch)) => {
                        out.push(ch);
                        self.i += e.len();
                    }
                    None => {
                        out.push('&');
                        self.i += 1;
                    }
                }
                start = self.i;
                blank_run = false;
                continue;
            }
            if c < b' ' || c == 0x7f {
                out.push_str(&self.src[start..self.i]);
                if !blank_run {
                    out.push(' ');
                }
                blank_run = true;
                self.i += 1;
                start = self.i;
                continue;
            }
            blank_run = false;
            self.i += 1;
        }
        out.push_str(&self.src[start..self.i]);
        out
    }

    /// A quoted string or option: the opening character is at `self.i`.
    fn delimited(&mut self, close: u8, what: &str) -> Result<String, GenError> {
        let start = self.i;
        self.i += 1;
        let s = self.escaped(Some(close));
        match self.peek() {
            Some(c) if c == close => {
                self.i += 1;
                Ok(s)
            }
            Some(c) => Err(self.err(self.i, format!("`{}` in {what}: libFAUDES writes it as an entity", c as char))),
            None => Err(self.err(start, format!("unterminated {what}"))),
        }
    }

    fn skip_blanks(&mut self) {
        while self.peek().is_some_and(is_space) {
            self.i += 1;
        }
    }

    fn name(&mut self) -> &'a str {
        let s = self.i;
        while let Some(c) = self.peek() {
            if c == b'>' || c == b'/' || is_space(c) {
                break;
            }
            self.i += 1;
        }
        &self.src[s..self.i]
    }

    /// Markup after `<` (`Token::ReadMarkup`), pushed to `out`; comments, declarations and
    /// processing instructions push nothing.
    fn markup(&mut self, start: usize, out: &mut Vec<Tok>) -> Result<(), GenError> {
        let rest = &self.src[self.i..];
        if let Some(comment) = rest.strip_prefix("!--") {
            return match comment.find("-->") {
                Some(k) => {
                    self.i += 3 + k + 3;
                    Ok(())
                }
                None => Err(self.err(start, "unterminated comment `<!--`")),
            };
        }
        if rest.starts_with("![CDATA[") {
            return match rest.find("]]>") {
                Some(k) => {
                    let text = rest[8..k].to_string();
                    self.i += k + 3;
                    out.push(Tok { kind: Kind::Text { text, number: Number::No }, span: Span::new(start, self.i) });
                    Ok(())
                }
                None => Err(self.err(start, "unterminated `<![CDATA[`")),
            };
        }
        if rest.starts_with("!D") || rest.starts_with("!d") {
            return match rest.find('>') {
                Some(k) => {
                    self.i += k + 1;
                    Ok(())
                }
                None => Err(self.err(start, "unterminated `<!DOCTYPE`")),
            };
        }
        if rest.starts_with('?') {
            return match rest.find("?>") {
                Some(k) => {
                    self.i += k + 2;
                    Ok(())
                }
                None => Err(self.err(start, "unterminated `<?`")),
            };
        }
        if rest.starts_with('/') {
            self.i += 1;
            let name = self.name();
            if name.is_empty() || self.peek() != Some(b'>') {
                return Err(self.err(start, "malformed end tag: expected `</Name>`"));
            }
            self.i += 1;
            out.push(Tok { kind: Kind::End(name.to_string()), span: Span::new(start, self.i) });
            return Ok(());
        }
        if !rest.starts_with(|c: char| c.is_ascii_alphabetic() || c == '_' || c == ':') {
            return Err(self.err(start, "malformed markup: expected a tag name after `<`"));
        }
        let name = self.name().to_string();
        let mut attrs = Vec::new();
        loop {
            self.skip_blanks();
            let key_start = self.i;
            while let Some(c) = self.peek() {
                if is_space(c) || c == b'=' || c == b'>' || c == b'/' {
                    break;
                }
                self.i += 1;
            }
            if self.i == key_start {
                break;
            }
            let key = self.src[key_start..self.i].to_string();
            self.skip_blanks();
            if self.peek() != Some(b'=') {
                return Err(self.err(key_start, format!("attribute `{key}` in <{name}> needs `=` and a value")));
            }
            self.i += 1;
            self.skip_blanks();
            let value = match self.peek() {
                Some(q @ (b'"' | b'\'')) => self.delimited(q, "attribute value")?,
                _ => self.escaped(None),
            };
            attrs.push((key, value));
        }
        let empty = self.peek() == Some(b'/');
        if empty {
            self.i += 1;
        }
        if self.peek() != Some(b'>') {
            return Err(self.err(start, format!("malformed tag <{name}>: expected `>`")));
        }
        self.i += 1;
        let span = Span::new(start, self.i);
        out.push(Tok { kind: Kind::Begin { name: name.clone(), attrs }, span });
        if empty {
            out.push(Tok { kind: Kind::End(name), span });
        }
        Ok(())
    }

    fn tokens(mut self) -> Result<Vec<Tok>, GenError> {
        let mut out = Vec::new();
        while let Some(c) = self.peek() {
            let start = self.i;
            match c {
                c if is_space(c) => self.i += 1,
                b'%' => {
                    while self.peek().is_some_and(|c| c != b'\n' && c != b'\r') {
                        self.i += 1;
                    }
                }
                b'<' => {
                    self.i += 1;
                    self.markup(start, &mut out)?;
                }
                b'"' | b'\'' => {
                    let text = self.delimited(c, "quoted string")?;
                    out.push(Tok { kind: Kind::Text { text, number: Number::No }, span: Span::new(start, self.i) });
                }
                b'+' => {
                    let option = self.delimited(b'+', "option `+…+`")?;
                    out.push(Tok { kind: Kind::Option(option), span: Span::new(start, self.i) });
                }
                b'=' => {
                    let Some(k) = self.src[start + 1..].find('=') else {
                        return Err(self.err(start, "unterminated binary data `=…=`"));
                    };
                    self.i = start + 1 + k + 1;
                    while self.peek() == Some(b'=') {
                        self.i += 1;
                    }
                    out.push(Tok { kind: Kind::Binary, span: Span::new(start, self.i) });
                }
                b'>' => return Err(self.err(start, "unexpected `>` outside a tag")),
                _ => {
                    let text = self.escaped(None);
                    let number = interpret_number(&text);
                    out.push(Tok { kind: Kind::Text { text, number }, span: Span::new(start, self.i) });
                }
            }
        }
        Ok(out)
    }
}

/// The tokens of a text and, for every begin tag, the index of its end tag.
struct Sections {
    toks: Vec<Tok>,
    close: Vec<usize>,
}

impl Sections {
    fn parse(src: &str) -> Result<Sections, GenError> {
        let toks = Lexer { src, b: src.as_bytes(), i: 0 }.tokens()?;
        let mut close = vec![usize::MAX; toks.len()];
        let mut open: Vec<usize> = Vec::new();
        for (i, t) in toks.iter().enumerate() {
            match &t.kind {
                Kind::Begin { .. } => open.push(i),
                Kind::End(name) => {
                    let Some(b) = open.pop() else {
                        return Err(GenError::at(t.span, format!("`</{name}>` closes no section")));
                    };
                    if !toks[b].is_begin(name) {
                        return Err(GenError::at(t.span, format!("`</{name}>` does not close {}", toks[b].describe()))
                            .note(format!("expected `</{}>`", tag_name(&toks[b]))));
                    }
                    close[b] = i;
                }
                _ => {}
            }
        }
        if let Some(&b) = open.last() {
            let name = tag_name(&toks[b]);
            return Err(GenError::at(toks[b].span, format!("missing </{name}> for this <{name}>")));
        }
        Ok(Sections { toks, close })
    }

    /// The index after `i`'s token or, for a section, after its end tag.
    fn next(&self, i: usize) -> usize {
        match self.toks[i].kind {
            Kind::Begin { .. } => self.close[i] + 1,
            _ => i + 1,
        }
    }

    /// `AttrType::Skip`: passes over the attributes after an element (options, flags, numbers
    /// that are not indices, other sections) up to the next element or `<Consecutive>`.
    fn skip_attributes(&self, mut i: usize, end: usize) -> usize {
        while i < end {
            match self.toks[i].class() {
                Class::String | Class::Integer | Class::End => break,
                Class::Begin if self.toks[i].is_begin("Consecutive") => break,
                _ => i = self.next(i),
            }
        }
        i
    }

    /// The direct children `(index)` of the section opened at `b`.
    fn children(&self, b: usize) -> impl Iterator<Item = usize> + '_ {
        let end = self.close[b];
        std::iter::successors(Some(b + 1).filter(|&i| i < end), move |&i| Some(self.next(i)).filter(|&n| n < end))
    }
}

fn tag_name(t: &Tok) -> &str {
    match &t.kind {
        Kind::Begin { name, .. } | Kind::End(name) => name,
        _ => "",
    }
}

/// libFAUDES's controllability flag (`AttributeCFlags`, bit 0x01).
const CONTROLLABLE_FLAG: i64 = 0x01;

/// Reading state: the automaton under construction and libFAUDES's index bookkeeping.
struct Reader<'s, 'e> {
    s: &'s Sections,
    events: &'e mut Events,
    /// libFAUDES caps nothing; the caller's budget caps the states a file may declare, so that
    /// a 100-byte `<Consecutive>` range cannot take seconds and gigabytes (a decompression bomb
    /// for automata).
    max_states: usize,
    builder: AutomatonBuilder,
    by_index: HashMap<u64, StateId>,
    by_name: HashMap<String, StateId>,
    /// Each state as it is written (its name, or its index).
    labels: Vec<String>,
    max_index: u64,
    alphabet: Vec<ClassicEventId>,
    in_alphabet: HashSet<ClassicEventId>,
    event_spans: HashMap<ClassicEventId, Span>,
}

impl<'s> Reader<'s, '_> {
    fn tok(&self, i: usize) -> &'s Tok {
        &self.s.toks[i]
    }

    fn add_event(&mut self, name: &str, span: Span) -> ClassicEventId {
        let e = self.events.intern(name, false);
        if self.in_alphabet.insert(e) {
            self.alphabet.push(e);
            self.event_spans.insert(e, span);
        }
        e
    }

    fn add_state(&mut self, index: i64, name: Option<&str>, span: Span) -> Result<StateId, GenError> {
        if index <= 0 || index > u32::MAX as i64 {
            return Err(GenError::at(span, format!("state index {index} is out of range"))
                .note("libFAUDES numbers states from 1 to 4294967295"));
        }
        let index = index as u64;
        let label = name.map_or_else(|| index.to_string(), str::to_string);
        if self.by_index.contains_key(&index) || name.is_some_and(|n| self.by_name.contains_key(n)) {
            return Err(GenError::at(span, format!("state `{label}` (index {index}) appears twice")));
        }
        if self.labels.len() >= self.max_states {
            return Err(over_budget(span, self.max_states));
        }
        let s = self.builder.add_state(label.clone(), false);
        self.labels.push(label);
        self.by_index.insert(index, s);
        if let Some(n) = name {
            self.by_name.insert(n.to_string(), s);
        }
        self.max_index = self.max_index.max(index);
        Ok(s)
    }

    /// Adds the anonymous states `first..=last`, refusing a range beyond the state cap before
    /// building any of it.
    fn add_range(&mut self, first: i64, last: i64, span: Span) -> Result<usize, GenError> {
        if last < first {
            return Ok(0);
        }
        let count = (last as i128 - first as i128 + 1) as u128;
        if count + self.labels.len() as u128 > self.max_states as u128 {
            return Err(over_budget(span, self.max_states));
        }
        for k in first..=last {
            self.add_state(k, None, span)?;
        }
        Ok(count as usize)
    }

    /// A state named by an index or a name in `<TransRel>`, `<InitStates>` or `<MarkedStates>`.
    fn state(&self, i: usize, what: &str) -> Result<StateId, GenError> {
        let t = self.tok(i);
        if let Some(k) = t.integer() {
            return u64::try_from(k)
                .ok()
                .and_then(|k| self.by_index.get(&k).copied())
                .ok_or_else(|| GenError::at(t.span, format!("unknown state index {k}")));
        }
        match t.text() {
            Some(n) => self.by_name.get(n).copied().ok_or_else(|| GenError::at(t.span, format!("unknown state `{n}`"))),
            None => Err(GenError::at(t.span, format!("expected {what}, found {}", t.describe()))),
        }
    }

    /// Controllability flags after an event (`AttributeCFlags::DoRead`): `+C+`-style options
    /// (C sets, c clears), hexadecimal flags, or XML tags `<Controllable/>` and `<Flags/>`.
    /// Returns the index after the attributes.
    fn event_attributes(&mut self, e: ClassicEventId, mut i: usize, end: usize) -> usize {
        let mut flags: Option<i64> = None;
        if i < end {
            match &self.tok(i).kind {
                Kind::Text { number: Number::Hex(v), .. } => flags = Some(*v),
                Kind::Option(o) => {
                    let mut c = None;
                    if o.contains('C') {
                        c = Some(CONTROLLABLE_FLAG);
                    }
                    if o.contains('c') {
                        c = Some(0);
                    }
                    flags = c;
                }
                _ => {
                    while i < end {
                        let t = self.tok(i);
                        if t.is_begin("Flags") {
                            flags = t.attr("value").and_then(tok_integer).or(flags);
                        } else if t.is_begin("Controllable") {
                            let on = t.attr("value").and_then(tok_integer).is_none_or(|v| v != 0);
                            flags = Some(if on { CONTROLLABLE_FLAG } else { 0 });
                        } else if !(t.is_begin("Observable") || t.is_begin("Forcible") || t.is_begin("Preemptible")) {
                            break;
                        }
                        i = self.s.next(i);
                    }
                }
            }
        }
        if flags.is_some_and(|f| f & CONTROLLABLE_FLAG != 0) {
            self.events.set_controllable(e, true);
        }
        i
    }

    fn read_alphabet(&mut self, b: usize) -> Result<(), GenError> {
        let end = self.s.close[b];
        let mut i = b + 1;
        while i < end {
            let t = self.tok(i);
            if let Some(name) = t.text() {
                let (name, span) = (name.to_string(), t.span);
                let e = self.add_event(&name, span);
                i = self.event_attributes(e, i + 1, end);
                i = self.s.skip_attributes(i, end);
            } else if t.is_begin("Event") {
                let Some(name) = t.attr("name").map(str::to_string) else {
                    return Err(GenError::at(t.span, "<Event> without a name"));
                };
                let span = t.span;
                let e = self.add_event(&name, span);
                self.event_attributes(e, i + 1, self.s.close[i]);
                i = self.s.next(i);
            } else if let Kind::Option(o) = &t.kind {
                return Err(GenError::at(t.span, format!("attribute `+{o}+` before any event")));
            } else {
                return Err(GenError::at(t.span, format!("unexpected {} in <Alphabet>", t.describe())));
            }
        }
        Ok(())
    }

    /// Native `<States>` (`vGenerator::ReadStates`): a state without `#index` gets the count of
    /// states read so far plus one.
    fn read_states(&mut self, b: usize) -> Result<(), GenError> {
        let end = self.s.close[b];
        let mut next_index: i64 = 1;
        let (mut plain, mut suffixed) = (false, false);
        let mut i = b + 1;
        while i < end {
            let t = self.tok(i);
            let span = t.span;
            if let Some(k) = t.integer() {
                self.add_state(k, None, span)?;
            } else if t.is_begin("Consecutive") {
                let (first, last) = native_range(self.s, i)?;
                next_index += self.add_range(first, last, span)? as i64;
                i = self.s.next(i);
                continue;
            } else if let Some(text) = t.text() {
                let text = text.to_string();
                let (name, index) = match text.split_once('#') {
                    Some((name, suffix)) => {
                        suffixed = true;
                        let index = suffix.parse::<i64>().map_err(|_| {
                            GenError::at(span, format!("state `{text}`: `#` must be followed by the state's index"))
                        })?;
                        (name.to_string(), index)
                    }
                    None => {
                        plain = true;
                        (text, next_index)
                    }
                };
                if plain && suffixed {
                    return Err(GenError::at(span, "states with and without `#index` in one <States> section")
                        .note("libFAUDES writes `name#index` for every named state, or for none"));
                }
                if name.is_empty() {
                    return Err(GenError::at(span, "a state name cannot be empty"));
                }
                self.add_state(index, Some(&name), span)?;
            } else {
                return Err(GenError::at(span, format!("unexpected {} in <States>", t.describe())));
            }
            next_index += 1;
            i = self.s.skip_attributes(i + 1, end);
        }
        Ok(())
    }

    /// XML `<StateSet>` (`vGenerator::XReadStateSet`): states with their initial and marked flags.
    fn read_state_set(
        &mut self,
        b: usize,
        init: &mut Vec<(StateId, Span)>,
        marked: &mut Vec<StateId>,
    ) -> Result<(), GenError> {
        let sections = self.s;
        for i in sections.children(b) {
            let t = self.tok(i);
            let span = t.span;
            if t.is_begin("Consecutive") {
                let (first, last) = xml_range(t)?;
                self.add_range(first, last, span)?;
            } else if t.is_begin("State") {
                let name = t.attr("name").filter(|n| !n.is_empty()).map(str::to_string);
                let Some(index) = t.attr("id").and_then(tok_integer) else {
                    return Err(GenError::at(span, "<State> needs an integer `id`"));
                };
                let s = self.add_state(index, name.as_deref(), span)?;
                for c in sections.children(i) {
                    let flag = self.tok(c);
                    let on = flag.attr("value").and_then(tok_integer).is_none_or(|v| v != 0);
                    if flag.is_begin("Initial") {
                        if on {
                            init.push((s, flag.span));
                        }
                    } else if flag.is_begin("Marked") {
                        if on {
                            marked.push(s);
                        }
                    } else {
                        break;
                    }
                }
            }
        }
        Ok(())
    }

    /// Native `<TransRel>` (`vGenerator::ReadTransRel`). When no states are declared, the
    /// triples introduce them (by index or by name, not both); when the alphabet is empty,
    /// they introduce events.
    fn read_trans_rel(&mut self, b: usize) -> Result<Vec<(StateId, ClassicEventId, StateId, Span)>, GenError> {
        let end = self.s.close[b];
        let (mut new_by_index, mut new_by_name) = (self.labels.is_empty(), self.labels.is_empty());
        let new_events = self.alphabet.is_empty();
        let mut out = Vec::new();
        let mut i = b + 1;
        while i < end {
            let start = self.tok(i).span;
            let mut ends = [StateId::new(0); 2];
            let mut event = None;
            for (k, what) in ["a source state", "an event", "a target state"].into_iter().enumerate() {
                if i >= end {
                    return Err(GenError::at(start, "incomplete transition: expected source, event and target"));
                }
                let t = self.tok(i);
                if k == 1 {
                    let Some(name) = t.text() else {
                        return Err(GenError::at(t.span, format!("expected an event, found {}", t.describe())));
                    };
                    let e = match self.events.get(name).filter(|e| self.in_alphabet.contains(e)) {
                        Some(e) => e,
                        None if new_events => {
                            let (name, span) = (name.to_string(), t.span);
                            self.add_event(&name, span)
                        }
                        None => return Err(GenError::at(t.span, format!("event `{name}` is not in the alphabet"))),
                    };
                    event = Some(e);
                } else {
                    let s = match self.state(i, what) {
                        Ok(s) => s,
                        Err(e) => {
                            let span = t.span;
                            match (t.integer(), t.text()) {
                                (Some(k), _) if new_by_index => {
                                    new_by_name = false;
                                    self.add_state(k, None, span)?
                                }
                                (None, Some(n)) if new_by_name => {
                                    new_by_index = false;
                                    let n = n.to_string();
                                    self.add_state(self.max_index as i64 + 1, Some(&n), span)?
                                }
                                _ => return Err(e),
                            }
                        }
                    };
                    ends[k / 2] = s;
                }
                i += 1;
            }
            let e = event.expect("the loop reads an event");
            out.push((ends[0], e, ends[1], start.to(self.tok(i - 1).span)));
            i = self.s.skip_attributes(i, end);
        }
        Ok(out)
    }

    /// XML `<TransitionRelation>` (`vGenerator::XReadTransRel`).
    fn read_transition_relation(
        &mut self,
        b: usize,
    ) -> Result<Vec<(StateId, ClassicEventId, StateId, Span)>, GenError> {
        let mut out = Vec::new();
        let sections = self.s;
        for i in sections.children(b) {
            let t = self.tok(i);
            if !t.is_begin("Transition") {
                continue;
            }
            let state = |key: &str| -> Result<StateId, GenError> {
                let Some(v) = t.attr(key) else {
                    return Err(GenError::at(t.span, format!("<Transition> without `{key}`")));
                };
                let found = match tok_integer(v) {
                    Some(k) => u64::try_from(k).ok().and_then(|k| self.by_index.get(&k).copied()),
                    None => self.by_name.get(v).copied(),
                };
                found.ok_or_else(|| GenError::at(t.span, format!("unknown state `{v}` in `{key}`")))
            };
            let (x1, x2) = (state("x1")?, state("x2")?);
            let Some(name) = t.attr("event") else {
                return Err(GenError::at(t.span, "<Transition> without `event`"));
            };
            let Some(e) = self.events.get(name).filter(|e| self.in_alphabet.contains(e)) else {
                return Err(GenError::at(t.span, format!("event `{name}` is not in the alphabet")));
            };
            out.push((x1, e, x2, t.span));
        }
        Ok(out)
    }

    /// Native `<InitStates>`/`<MarkedStates>` (`vGenerator::ReadStateSet`): indices, names
    /// (without `#index`), `<Consecutive>` ranges and XML `<State>` elements of known states.
    fn read_state_list(&self, b: usize) -> Result<Vec<(StateId, Span)>, GenError> {
        let end = self.s.close[b];
        let mut out = Vec::new();
        let mut i = b + 1;
        while i < end {
            let t = self.tok(i);
            if t.is_begin("Consecutive") {
                let (first, last) = match t.attr("from") {
                    Some(_) => xml_range(t)?,
                    None => native_range(self.s, i)?,
                };
                for k in first..=last {
                    let s = self.by_index.get(&(k as u64)).copied();
                    out.push((s.ok_or_else(|| GenError::at(t.span, format!("unknown state index {k}")))?, t.span));
                }
                i = self.s.next(i);
            } else if t.is_begin("State") {
                let s = match (t.attr("id").and_then(tok_integer), t.attr("name")) {
                    (Some(k), _) => u64::try_from(k).ok().and_then(|k| self.by_index.get(&k).copied()),
                    (None, Some(n)) => self.by_name.get(n).copied(),
                    (None, None) => None,
                };
                out.push((s.ok_or_else(|| GenError::at(t.span, "unknown <State>"))?, t.span));
                i = self.s.next(i);
            } else if matches!(t.kind, Kind::Begin { .. }) {
                i = self.s.next(i);
            } else {
                if t.text().is_some_and(|n| n.contains('#')) && t.integer().is_none() {
                    return Err(GenError::at(t.span, format!("{}: no `#index` here, only in <States>", t.describe())));
                }
                out.push((self.state(i, "a state")?, t.span));
                i = self.s.skip_attributes(i + 1, end);
            }
        }
        Ok(out)
    }
}

/// An integer attribute value as libFAUDES interprets it.
fn tok_integer(v: &str) -> Option<i64> {
    match interpret_number(v) {
        Number::Integer(k) | Number::Hex(k) | Number::Boolean(k) => Some(k),
        _ => None,
    }
}

fn native_range(s: &Sections, b: usize) -> Result<(i64, i64), GenError> {
    let body: Vec<&Tok> = s.children(b).map(|i| &s.toks[i]).collect();
    match (body.first().and_then(|t| t.integer()), body.get(1).and_then(|t| t.integer())) {
        (Some(first), Some(last)) => Ok((first, last)),
        _ => Err(GenError::at(s.toks[b].span, "malformed <Consecutive> range: expected two indices")),
    }
}

fn xml_range(t: &Tok) -> Result<(i64, i64), GenError> {
    match (t.attr("from").and_then(tok_integer), t.attr("to").and_then(tok_integer)) {
        (Some(first), Some(last)) if first > 0 && last >= first => Ok((first, last)),
        _ => Err(GenError::at(t.span, "malformed <Consecutive> range: expected `from` and `to` with 0 < from <= to")),
    }
}

/// Reads a generator, adding its events to `events` (controllability from `+C+` attributes;
/// an event already known keeps being controllable if either source says so).
pub fn read_gen(src: &str, events: &mut Events) -> Result<Automaton, GenError> {
    read_gen_file(src, events).map(|f| f.automaton)
}

/// [`read_gen`], also telling where each event is named. At most
/// [`DEFAULT_MAX_STATES`](crate::sct::model::DEFAULT_MAX_STATES) states are read.
pub fn read_gen_file(src: &str, events: &mut Events) -> Result<GenFile, GenError> {
    read_gen_file_within(src, events, crate::sct::model::DEFAULT_MAX_STATES)
}

/// [`read_gen_file`] with a state budget: a file declaring more than `max_states` states is
/// refused (a [`GenError`] with `over_budget`) before they are built.
pub fn read_gen_file_within(src: &str, events: &mut Events, max_states: usize) -> Result<GenFile, GenError> {
    let s = Sections::parse(src)?;
    let top: Vec<usize> = std::iter::successors(Some(0).filter(|&i| i < s.toks.len()), |&i| {
        Some(s.next(i)).filter(|&n| n < s.toks.len())
    })
    .collect();
    let generator = top
        .iter()
        .copied()
        .find(|&i| s.toks[i].is_begin("Generator"))
        .or_else(|| top.iter().copied().find(|&i| matches!(s.toks[i].kind, Kind::Begin { .. })));
    let Some(g) = generator else {
        return Err(GenError::at(Span::new(0, 0), "no <Generator> section"));
    };
    let mut sections: HashMap<&'static str, usize> = HashMap::new();
    for (n, i) in s.children(g).enumerate() {
        let t = &s.toks[i];
        let Kind::Begin { name, .. } = &t.kind else {
            if n == 0 && t.text().is_some() {
                continue; // the generator's name
            }
            return Err(GenError::at(t.span, format!("unexpected {} in <{}>", t.describe(), tag_name(&s.toks[g])))
                .note("expected sections such as <Alphabet>, <States>, <TransRel>"));
        };
        let key = match name.as_str() {
            "Alphabet" | "A" => "Alphabet",
            "States" | "S" => "States",
            "StateSet" => "StateSet",
            "TransRel" | "T" => "TransRel",
            "TransitionRelation" => "TransitionRelation",
            "InitStates" | "I" => "InitStates",
            "MarkedStates" | "M" => "MarkedStates",
            _ => continue, // attributes of other generator types
        };
        if sections.insert(key, i).is_some() {
            return Err(GenError::at(t.span, format!("a second <{name}> section")));
        }
    }
    let both = |a: &str, b: &str| sections.contains_key(a) && sections.contains_key(b);
    if both("States", "StateSet") || both("TransRel", "TransitionRelation") {
        return Err(GenError::at(s.toks[g].span, "native and XML sections mixed in one generator")
            .note("libFAUDES writes <States>/<TransRel> (Write) or <StateSet>/<TransitionRelation> (XWrite)"));
    }
    let mut r = Reader {
        s: &s,
        events,
        max_states,
        builder: AutomatonBuilder::new(),
        by_index: HashMap::new(),
        by_name: HashMap::new(),
        labels: Vec::new(),
        max_index: 0,
        alphabet: Vec::new(),
        in_alphabet: HashSet::new(),
        event_spans: HashMap::new(),
    };
    if let Some(&b) = sections.get("Alphabet") {
        r.read_alphabet(b)?;
    }
    let mut init: Vec<(StateId, Span)> = Vec::new();
    let mut marked: Vec<StateId> = Vec::new();
    if let Some(&b) = sections.get("States") {
        r.read_states(b)?;
    }
    if let Some(&b) = sections.get("StateSet") {
        r.read_state_set(b, &mut init, &mut marked)?;
    }
    let mut trans = Vec::new();
    if let Some(&b) = sections.get("TransRel") {
        trans = r.read_trans_rel(b)?;
    }
    if let Some(&b) = sections.get("TransitionRelation") {
        trans = r.read_transition_relation(b)?;
    }
    if let Some(&b) = sections.get("InitStates") {
        init.extend(r.read_state_list(b)?);
    }
    if let Some(&b) = sections.get("MarkedStates") {
        marked.extend(r.read_state_list(b)?.into_iter().map(|(s, _)| s));
    }
    // Deterministic: one initial state, one target per state and event.
    let mut initial: Option<StateId> = None;
    for &(st, span) in &init {
        match initial {
            Some(first) if first != st => {
                return Err(GenError::at(
                    span,
                    format!(
                        "a second initial state `{}` (the first is `{}`)",
                        r.labels[st.index()],
                        r.labels[first.index()]
                    ),
                )
                .note("SupCon needs deterministic generators: one initial state"));
            }
            _ => initial = Some(st),
        }
    }
    let mut seen: HashMap<(StateId, ClassicEventId), StateId> = HashMap::new();
    for &(x1, e, x2, span) in &trans {
        match seen.get(&(x1, e)) {
            Some(&t) if t != x2 => {
                return Err(GenError::at(
                    span,
                    format!(
                        "state `{}` has two transitions on event `{}` (to `{}` and `{}`)",
                        r.labels[x1.index()],
                        r.events.name(e),
                        r.labels[t.index()],
                        r.labels[x2.index()]
                    ),
                )
                .note("SupCon needs deterministic generators"));
            }
            Some(_) => {}
            None => {
                seen.insert((x1, e), x2);
                r.builder.add_transition(x1, e, x2);
            }
        }
    }
    for &e in &r.alphabet {
        r.builder.add_event(e);
    }
    for m in marked {
        r.builder.set_marked(m, true);
    }
    if let Some(i) = initial {
        r.builder.set_init(i);
    }
    let Reader { builder, event_spans, .. } = r;
    // The checks above leave nothing for `build` to refuse; say so plainly if it does.
    let automaton = builder.build().map_err(|e| {
        let what = match e {
            BuildError::Nondeterministic { .. } => "a nondeterministic transition",
            BuildError::EventNotInAlphabet { .. } => "a transition on an event outside the alphabet",
            BuildError::BadState { .. } => "a transition to an unknown state",
        };
        GenError::at(s.toks[g].span, format!("invalid generator: {what}"))
    })?;
    Ok(GenFile { automaton, event_spans })
}

/// `<>&"` as libFAUDES's entities (`Token::WriteEscapedString`).
fn escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '&' => out.push_str("&amp;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
    out
}

/// A name as libFAUDES's `Token::Write` writes it (bare if it starts with a letter and has no
/// blank, quoted otherwise), also quoted where libFAUDES would read the bare word as a number
/// (`true`, `inf`).
fn token(s: &str) -> String {
    let bare = s.starts_with(|c: char| c.is_ascii_alphabetic())
        && !s.contains(|c: char| c.is_whitespace() || c.is_control())
        && interpret_number(s) == Number::No;
    if bare {
        escape(s)
    } else {
        format!("\"{}\"", escape(s))
    }
}

/// Writes a generator in libFAUDES's native format; controllable events carry `+C+`, empty
/// sections are self-closing as libFAUDES writes them.
pub fn write_gen(a: &Automaton, events: &Events, name: &str) -> String {
    fn section(o: &mut String, tag: &str, lines: Vec<String>) {
        if lines.is_empty() {
            let _ = writeln!(o, "<{tag}/>");
        } else {
            let _ = writeln!(o, "<{tag}>");
            for l in lines {
                let _ = writeln!(o, "{l}");
            }
            let _ = writeln!(o, "</{tag}>");
        }
    }
    // State names: s<id> keeps them unique regardless of the original names.
    let state = |s: StateId| format!("s{s}");
    let states = (0..a.num_states()).map(StateId::new);
    let mut o = format!("<Generator>\n\"{}\"\n", escape(name));
    let alphabet = a
        .alphabet()
        .iter()
        .map(|&e| format!("{}{}", token(events.name(e)), if events.is_controllable(e) { " +C+" } else { "" }));
    section(&mut o, "Alphabet", alphabet.collect());
    section(&mut o, "States", states.clone().map(state).collect());
    let trans = states.clone().flat_map(|s| {
        a.edges(s).iter().map(move |e| format!("{} {} {}", state(s), token(events.name(e.event)), state(e.target)))
    });
    section(&mut o, "TransRel", trans.collect());
    section(&mut o, "InitStates", a.init().into_iter().map(state).collect());
    section(&mut o, "MarkedStates", states.filter(|&s| a.is_marked(s)).map(state).collect());
    o.push_str("</Generator>\n");
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
    fn reads_self_closing_empty_sections() {
        let src =
            "<Generator name=\"e\">\n<Alphabet/>\n<States/>\n<TransRel/>\n<InitStates/>\n<MarkedStates/>\n</Generator>";
        let a = read_gen(src, &mut Events::new()).unwrap();
        assert_eq!((a.num_states(), a.num_transitions(), a.alphabet().len(), a.init()), (0, 0, 0, None));
        let src = "<Generator> <Alphabet> a +C+ </Alphabet> <States> 1 2 </States> <TransRel/> <InitStates> 1 </InitStates> <MarkedStates/> </Generator>";
        let mut ev = Events::new();
        let a = read_gen(src, &mut ev).unwrap();
        assert_eq!((a.num_states(), a.num_transitions(), a.init()), (2, 0, Some(StateId::new(0))));
        assert!(
            !a.is_marked(StateId::new(0)) && !a.is_marked(StateId::new(1)) && ev.is_controllable(ev.get("a").unwrap())
        );
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

    /// Names that libFAUDES would misread bare (numbers, `true`, markup characters) are quoted
    /// or escaped, and read back as they were.
    #[test]
    fn writer_quotes_and_escapes_names() {
        let mut ev = Events::new();
        let names = ["true", "1x", "a<b>&\"c\"", "inf", "0x1F", "x y", "plain"];
        let ids: Vec<ClassicEventId> = names.iter().map(|n| ev.intern(n, n.len() % 2 == 0)).collect();
        let mut b = AutomatonBuilder::new();
        let s = b.add_state("s", true);
        for &e in &ids {
            b.add_event(e);
            b.add_transition(s, e, s);
        }
        b.set_init(s);
        let a = b.build().unwrap();
        let text = write_gen(&a, &ev, "name with \"quotes\"");
        assert!(
            text.contains(" a&lt;b&gt;&amp;&quot;c&quot; ") && text.contains(" \"true\" ") && text.contains(" \"1x\" ")
        );
        assert!(text.contains("\n\"name with &quot;quotes&quot;\"\n"));
        let mut ev2 = Events::new();
        let back = read_gen(&text, &mut ev2).unwrap();
        assert_eq!(back.num_transitions(), names.len());
        for n in names {
            let e = ev2.get(n).unwrap_or_else(|| panic!("`{n}` not read back from\n{text}"));
            assert_eq!(ev2.is_controllable(e), n.len() % 2 == 0, "{n}");
        }
    }

    /// The error of `src` as (line, column, message, notes).
    fn error(src: &str) -> (u32, u32, String, Vec<String>) {
        let e = read_gen(src, &mut Events::new()).unwrap_err();
        let d = e.diagnostic(src);
        assert!(!d.message.contains('{') && !d.message.contains("ClassicEventId"), "debug text: {}", d.message);
        (d.line, d.column, d.message, d.notes)
    }

    #[test]
    fn nondeterminism_is_located_at_the_second_transition() {
        let src = "<Generator>\n<Alphabet> a </Alphabet>\n<States> 3 4 7 </States>\n<TransRel>\n3 a 4\n  3 a 7\n</TransRel>\n</Generator>";
        let (line, column, message, notes) = error(src);
        assert_eq!((line, column), (6, 3));
        assert_eq!(message, "state `3` has two transitions on event `a` (to `4` and `7`)");
        assert_eq!(notes, ["SupCon needs deterministic generators"]);
        let src = "<Generator> <Alphabet> a </Alphabet> <States> idle busy </States>\n<TransRel> idle a busy </TransRel>\n<InitStates> idle\n busy </InitStates> </Generator>";
        let (line, column, message, notes) = error(src);
        assert_eq!((line, column, message.as_str()), (4, 2, "a second initial state `busy` (the first is `idle`)"));
        assert_eq!(notes, ["SupCon needs deterministic generators: one initial state"]);
        // The same in the XML format: the second `<Initial/>`.
        let src = "<Generator> <Alphabet/> <StateSet>\n<State id=\"1\"><Initial/></State>\n<State id=\"2\"> <Initial/> </State>\n</StateSet> <TransitionRelation/> </Generator>";
        let (line, column, message, _) = error(src);
        assert_eq!((line, column, message.as_str()), (3, 16, "a second initial state `2` (the first is `1`)"));
    }

    #[test]
    fn every_error_is_located() {
        let cases: &[(&str, (u32, u32), &str)] = &[
            ("<Generator> <Alphabet> a </Alphabet> <States> 1 </States>\n<TransRel> 1 zz 1 </TransRel> </Generator>", (2, 14), "event `zz` is not in the alphabet"),
            ("<Generator>\n<Alphabet> a\n</States>", (3, 1), "`</States>` does not close <Alphabet>"),
            ("<Generator>\n  <TransRel> 1 a 1", (2, 3), "missing </TransRel> for this <TransRel>"),
            ("<Generator> <States> \"open", (1, 22), "unterminated quoted string"),
            ("<Generator> <Alphabet> a </Alphabet> <States> 1 </States> <TransRel> 1 a </TransRel> </Generator>", (1, 70), "incomplete transition: expected source, event and target"),
            ("<Generator> <Alphabet> a </Alphabet> <States> 1 </States> <TransRel> 1 a 9 </TransRel> </Generator>", (1, 74), "unknown state index 9"),
            ("<Generator> <States> x#1 </States> <InitStates> x#1 </InitStates> </Generator>", (1, 49), "`x#1`: no `#index` here, only in <States>"),
            ("<Generator> <States> x#1 y </States> </Generator>", (1, 26), "states with and without `#index` in one <States> section"),
            ("<Generator> <States> 2 2 </States> </Generator>", (1, 24), "state `2` (index 2) appears twice"),
            ("<Generator> <States> 0 </States> </Generator>", (1, 22), "state index 0 is out of range"),
            ("<Generator> <Alphabet> +C+ a </Alphabet> </Generator>", (1, 24), "attribute `+C+` before any event"),
            ("<Generator> <States> <Consecutive> 1 </Consecutive> </States> </Generator>", (1, 22), "malformed <Consecutive> range: expected two indices"),
            ("<Generator> <States> <Consecutive> 1 99999999999 </Consecutive> </States> </Generator>", (1, 22), "the generator declares more than 250000 states, the state budget"),
            ("<Generator> x <Alphabet/> y </Generator>", (1, 27), "unexpected `y` in <Generator>"),
            ("<Generator> <Alphabet/> <Alphabet/> </Generator>", (1, 25), "a second <Alphabet> section"),
            ("% only a comment\n", (1, 1), "no <Generator> section"),
            ("<Generator> < Alphabet> </Generator>", (1, 13), "malformed markup: expected a tag name after `<`"),
            ("<Generator> <StateSet> <State name=\"p\"/> </StateSet> </Generator>", (1, 24), "<State> needs an integer `id`"),
            ("<Generator> <Alphabet> <Event name='a'/> </Alphabet> <StateSet> <State id='1'/> </StateSet>\n<TransitionRelation> <Transition x1='1' event='b' x2='1'/> </TransitionRelation> </Generator>", (2, 22), "event `b` is not in the alphabet"),
            ("<Generator> <States/> <TransRel/> <States/> <StateSet/> </Generator>", (1, 35), "a second <States> section"),
        ];
        for (src, at, message) in cases {
            let (line, column, got, _) = error(src);
            assert_eq!((line, column, got.as_str()), (at.0, at.1, *message), "{src}");
        }
    }

    #[test]
    fn event_spans_point_at_the_alphabet() {
        let src = "<Generator> <Alphabet> a\n  b +C+ </Alphabet> <States> 1 </States> <TransRel> 1 b 1 </TransRel> </Generator>";
        let mut ev = Events::new();
        let g = read_gen_file(src, &mut ev).unwrap();
        let span = g.event_span(ev.get("b").unwrap()).unwrap();
        assert_eq!(&src[span.range()], "b");
        assert_eq!(span.start as usize, src.find("\n  b").unwrap() + 3);
        // Introduced by <TransRel> when the alphabet is empty: the first use.
        let src = "<Generator> <TransRel> p go q </TransRel> </Generator>";
        let g = read_gen_file(src, &mut ev).unwrap();
        assert_eq!(&src[g.event_span(ev.get("go").unwrap()).unwrap().range()], "go");
    }
}
