//! The `.sct` parser: recursive descent that recovers at `;` and `}`, so that every syntax error
//! of a file is reported at once. The grammar is documented in `docs/sct-language.md`.

use super::ast::*;
use super::lexer::{lex, Tok};
use crate::diag::{Diagnostics, Span};
use crate::syntax::Cursor;

/// Words that start an item; error recovery stops in front of them.
const ITEM_KEYWORDS: &[&str] = &[
    "module",
    "event",
    "timer",
    "plant",
    "spec",
    "template",
    "instance",
    "state",
    "alphabet",
    "selfloops",
    "bind",
    "namespace",
];

struct Parser<'s, 'd> {
    src: &'s str,
    cur: Cursor<Tok>,
    diags: &'d mut Diagnostics<'s>,
    /// Modules currently open around the parse position.
    module_depth: usize,
}

type PResult<T> = Result<T, ()>;

/// How deeply modules may nest. Projects nest a few levels; the bound keeps the recursive
/// parser and project builder far from the stack limit of a wasm worker.
const MAX_MODULE_NESTING: usize = 64;

/// Parses a `.sct` file. Returns the items that could be parsed; errors go to `diags`.
pub fn parse<'s>(src: &'s str, diags: &mut Diagnostics<'s>) -> Vec<Item> {
    let toks = lex(src, diags);
    let mut p = Parser { src, cur: Cursor::new(toks), diags, module_depth: 0 };
    let mut items = Vec::new();
    while !p.cur.at(Tok::Eof) {
        let before = p.cur.pos();
        match p.item() {
            Ok(Some(i)) => items.push(i),
            Ok(None) => {}
            Err(()) => {
                if p.cur.pos() == before {
                    p.cur.bump();
                }
                p.recover_item();
                if p.cur.at(Tok::RBrace) {
                    let sp = p.cur.bump().1;
                    p.diags.error(sp, "unmatched `}`");
                }
            }
        }
    }
    items
}

impl<'s> Parser<'s, '_> {
    fn text(&self) -> &'s str {
        &self.src[self.cur.span().range()]
    }

    fn is_kw(&self, kw: &str) -> bool {
        self.cur.at(Tok::Ident) && self.text() == kw
    }

    fn describe(&self) -> String {
        match self.cur.peek() {
            Tok::Eof => "end of file".into(),
            _ => format!("`{}`", self.text()),
        }
    }

    fn err<T>(&mut self, expected: &str) -> PResult<T> {
        let span = self.cur.span();
        let found = self.describe();
        self.diags.error(span, format!("expected {expected}, found {found}"));
        Err(())
    }

    fn expect(&mut self, t: Tok, what: &str) -> PResult<Span> {
        if self.cur.at(t) {
            Ok(self.cur.bump().1)
        } else {
            self.err(what)
        }
    }

    fn expect_kw(&mut self, kw: &str) -> PResult<Span> {
        if self.is_kw(kw) {
            Ok(self.cur.bump().1)
        } else {
            self.err(&format!("`{kw}`"))
        }
    }

    fn ident(&mut self, what: &str) -> PResult<(String, Span)> {
        if self.cur.at(Tok::Ident) {
            let s = self.text().to_string();
            Ok((s, self.cur.bump().1))
        } else {
            self.err(what)
        }
    }

    /// A string literal's text and the span of the literal (quotes included).
    fn string_at(&mut self, what: &str) -> PResult<(String, Span)> {
        if self.cur.at(Tok::Str) {
            let t = self.text();
            let span = self.cur.bump().1;
            Ok((unescape(&t[1..t.len() - 1]), span))
        } else {
            self.err(what)
        }
    }

    fn path(&mut self, what: &str) -> PResult<Path> {
        let (first, mut span) = self.ident(what)?;
        let mut parts = vec![first];
        while self.cur.at(Tok::Dot) && self.cur.peek_at(1) == Tok::Ident {
            self.cur.bump();
            let (p, s) = self.ident("a name")?;
            parts.push(p);
            span = span.to(s);
        }
        Ok(Path { parts, span })
    }

    fn path_list(&mut self, what: &str) -> PResult<Vec<Path>> {
        let mut v = vec![self.path(what)?];
        while self.cur.at(Tok::Comma) {
            self.cur.bump();
            v.push(self.path(what)?);
        }
        Ok(v)
    }

    /// Skips to the end of the current item: past the next `;` at depth 0 or past a balanced
    /// `{ ... }` block, or up to a `}` that closes an enclosing block.
    fn recover_item(&mut self) {
        let mut depth = 0usize;
        loop {
            match self.cur.peek() {
                Tok::Eof => return,
                Tok::Ident if depth == 0 && ITEM_KEYWORDS.contains(&self.text()) => return,
                Tok::Semi if depth == 0 => {
                    self.cur.bump();
                    return;
                }
                Tok::LBrace => depth += 1,
                Tok::RBrace => {
                    if depth == 0 {
                        return;
                    }
                    depth -= 1;
                    if depth == 0 {
                        self.cur.bump();
                        return;
                    }
                }
                _ => {}
            }
            self.cur.bump();
        }
    }

    /// Parses `{ inner* }` calling `inner` until the closing brace, recovering per element.
    fn block(&mut self, mut inner: impl FnMut(&mut Self) -> PResult<()>) -> PResult<Span> {
        self.expect(Tok::LBrace, "`{`")?;
        loop {
            match self.cur.peek() {
                Tok::RBrace => return Ok(self.cur.bump().1),
                Tok::Eof => {
                    return self.err("`}`");
                }
                _ => {
                    let before = self.cur.pos();
                    if inner(self).is_err() {
                        if self.cur.pos() == before {
                            self.cur.bump();
                        }
                        self.recover_item();
                    }
                }
            }
        }
    }

    fn item(&mut self) -> PResult<Option<Item>> {
        if !self.cur.at(Tok::Ident) {
            self.err("an item (`module`, `event`, `timer`, `plant`, `spec`, `template` or `instance`)")?;
        }
        match self.text() {
            "module" => {
                if self.module_depth >= MAX_MODULE_NESTING {
                    let span = self.cur.span();
                    self.diags.error(span, format!("module nested too deeply: at most {MAX_MODULE_NESTING} levels"));
                    return Err(());
                }
                self.cur.bump();
                let (name, name_span) = self.ident("a module name")?;
                let mut items = Vec::new();
                self.module_depth += 1;
                let body = self.block(|p| {
                    if let Some(i) = p.item()? {
                        items.push(i);
                    }
                    Ok(())
                });
                self.module_depth -= 1;
                body?;
                Ok(Some(Item::Module { name, name_span, items }))
            }
            "event" => self.event().map(|e| Some(Item::Event(e))),
            "timer" => self.timer().map(|t| Some(Item::Timer(t))),
            "spec" if self.cur.peek_at(1) == Tok::Ident && self.cur.peek_at(2) == Tok::Eq => {
                self.cur.bump();
                let (name, name_span) = self.ident("a specification name")?;
                self.cur.bump();
                let mut operands = vec![self.path("a specification")?];
                while self.cur.at(Tok::Bar) {
                    self.cur.bump();
                    operands.push(self.path("a specification")?);
                }
                if operands.len() < 2 {
                    return self.err("`|` and a second specification");
                }
                self.expect(Tok::Semi, "`;`")?;
                Ok(Some(Item::SpecProduct { name, name_span, operands }))
            }
            "plant" | "spec" => {
                let kind = if self.text() == "plant" { AutKind::Plant } else { AutKind::Spec };
                self.cur.bump();
                self.automaton(kind, false).map(|a| Some(Item::Automaton(a)))
            }
            "template" => {
                self.cur.bump();
                let kind = if self.is_kw("plant") {
                    AutKind::Plant
                } else if self.is_kw("spec") {
                    AutKind::Spec
                } else {
                    return self.err("`plant` or `spec` after `template`");
                };
                self.cur.bump();
                self.automaton(kind, true).map(|a| Some(Item::Template(a)))
            }
            "instance" => self.instance().map(|i| Some(Item::Instance(i))),
            _ => self.err("an item (`module`, `event`, `timer`, `plant`, `spec`, `template` or `instance`)"),
        }
    }

    fn event(&mut self) -> PResult<EventDecl> {
        use crate::sct::model::EventKind;
        self.cur.bump();
        let (name, name_span) = self.ident("an event name")?;
        self.expect(Tok::Colon, "`:` and the event type")?;
        let kind_span = self.cur.span();
        let kind = match self.ident("an event type")?.0.as_str() {
            "controllable" => Some(EventKind::Controllable),
            "uncontrollable" => Some(EventKind::Uncontrollable),
            "enforceable" => Some(EventKind::Enforceable),
            other => {
                self.diags
                    .error(kind_span, format!("unknown event type `{other}`"))
                    .with_note("expected `controllable`, `uncontrollable` or `enforceable`");
                None
            }
        };
        let mut items = Vec::new();
        if self.cur.at(Tok::Semi) {
            self.cur.bump();
        } else {
            self.block(|p| {
                let start = p.cur.span();
                let kw = p.ident("an event property")?.0;
                let item = match kw.as_str() {
                    "detect" => {
                        let (e, es) = p.ident("`rising`, `falling`, `edge` or `cyclic`")?;
                        let edge = match e.as_str() {
                            "rising" => EdgeKind::Rising,
                            "falling" => EdgeKind::Falling,
                            "edge" => EdgeKind::Either,
                            "cyclic" => EdgeKind::Cyclic,
                            _ => {
                                p.diags
                                    .error(es, format!("unknown trigger `{e}`"))
                                    .with_note("expected `rising`, `falling`, `edge` or `cyclic`");
                                return Err(());
                            }
                        };
                        let (expr, expr_span) = p.string_at("the trigger expression as a string")?;
                        EventItem::Detect { edge, expr, expr_span, span: start.to(es) }
                    }
                    "executed" => EventItem::Executed { span: start },
                    "reset" => {
                        p.expect_kw("on")?;
                        p.expect_kw("denial")?;
                        let mut addrs = vec![p.string_at("an address string")?];
                        while p.cur.at(Tok::Comma) {
                            p.cur.bump();
                            addrs.push(p.string_at("an address string")?);
                        }
                        EventItem::ResetOnDenial { addrs, span: start }
                    }
                    "on" => {
                        let (w, ws) = p.ident("`accept` or `denial`")?;
                        let (code, code_span) = p.string_at("the code as a string")?;
                        match w.as_str() {
                            "accept" => EventItem::OnAccept { code, code_span, span: start.to(ws) },
                            "denial" => EventItem::OnDenial { code, code_span, span: start.to(ws) },
                            _ => {
                                p.diags.error(ws, format!("expected `accept` or `denial`, found `{w}`"));
                                return Err(());
                            }
                        }
                    }
                    _ => {
                        p.diags
                            .error(start, format!("unknown event property `{kw}`"))
                            .with_note("expected `detect`, `executed`, `reset on denial`, `on accept` or `on denial`");
                        return Err(());
                    }
                };
                p.expect(Tok::Semi, "`;`")?;
                items.push(item);
                Ok(())
            })?;
        }
        Ok(EventDecl { name, name_span, kind, items })
    }

    fn timer(&mut self) -> PResult<TimerDecl> {
        self.cur.bump();
        let (name, name_span) = self.ident("a timer name")?;
        let mut t = TimerDecl { name, name_span, duration_ms: None, start: None, stops: Vec::new() };
        self.block(|p| {
            let (kw, ks) = p.ident("`duration`, `start` or `stop`")?;
            match kw.as_str() {
                "duration" => {
                    let mut total: u64 = 0;
                    let mut any = false;
                    while p.cur.at(Tok::Duration) {
                        let txt = p.text();
                        let split = txt.find(|c: char| !c.is_ascii_digit()).unwrap_or(txt.len());
                        let n: u64 = txt[..split].parse().unwrap_or(u64::MAX / 4_000_000);
                        let unit = match &txt[split..] {
                            "ms" => 1,
                            "s" => 1000,
                            "m" => 60_000,
                            _ => 3_600_000,
                        };
                        total = total.saturating_add(n.saturating_mul(unit));
                        any = true;
                        p.cur.bump();
                    }
                    if !any {
                        return p.err("a duration such as `15s` or `1m 30s`");
                    }
                    t.duration_ms = Some(total);
                }
                "start" => t.start = Some(p.path("the start event")?),
                "stop" => t.stops.extend(p.path_list("a stop event")?),
                _ => {
                    p.diags
                        .error(ks, format!("unknown timer property `{kw}`"))
                        .with_note("expected `duration`, `start` or `stop`");
                    return Err(());
                }
            }
            p.expect(Tok::Semi, "`;`")?;
            Ok(())
        })?;
        Ok(t)
    }

    fn automaton(&mut self, kind: AutKind, template: bool) -> PResult<AutDecl> {
        let (name, name_span) = self.ident("an automaton name")?;
        let mut a = AutDecl {
            kind,
            name,
            name_span,
            alphabet: None,
            selfloops: None,
            states: Vec::new(),
            binds: Vec::new(),
            namespaces: Vec::new(),
        };
        self.block(|p| {
            let (kw, ks) = p.ident("`alphabet`, `selfloops` or `state`")?;
            match kw.as_str() {
                "alphabet" => {
                    let list = p.path_list("an event")?;
                    p.expect(Tok::Semi, "`;`")?;
                    if let Some((_, prev)) = &a.alphabet {
                        let prev = *prev;
                        p.diags
                            .error(ks, "second `alphabet` declaration")
                            .with_note(format!("first declared at byte {}", prev.start));
                    }
                    a.alphabet = Some((list, ks));
                }
                "selfloops" => {
                    p.expect(Tok::Semi, "`;`")?;
                    a.selfloops = Some(ks);
                }
                "state" => {
                    let st = p.state()?;
                    a.states.push(st);
                }
                "bind" if template => {
                    a.binds.push(p.ident("a binding event")?);
                    while p.cur.at(Tok::Comma) {
                        p.cur.bump();
                        a.binds.push(p.ident("a binding event")?);
                    }
                    p.expect(Tok::Semi, "`;`")?;
                }
                "namespace" if template => {
                    let (ns, nss) = p.ident("a namespace name")?;
                    let mut evs = Vec::new();
                    p.expect(Tok::LBrace, "`{`")?;
                    while p.cur.at(Tok::Ident) {
                        evs.push(p.ident("a binding event")?);
                        if p.cur.at(Tok::Comma) {
                            p.cur.bump();
                        } else {
                            break;
                        }
                    }
                    p.expect(Tok::RBrace, "`}`")?;
                    a.namespaces.push((ns, nss, evs));
                }
                _ => {
                    let extra = if template { ", `bind`, `namespace`" } else { "" };
                    p.diags
                        .error(ks, format!("unknown automaton item `{kw}`"))
                        .with_note(format!("expected `alphabet`, `selfloops`{extra} or `state`"));
                    return Err(());
                }
            }
            Ok(())
        })?;
        Ok(a)
    }

    fn state(&mut self) -> PResult<StateDecl> {
        let (name, span) = self.ident("a state name")?;
        let mut st = StateDecl { name, span, initial: false, items: Vec::new() };
        if self.is_kw("initial") {
            self.cur.bump();
            st.initial = true;
        }
        if self.cur.at(Tok::Semi) {
            self.cur.bump();
            return Ok(st);
        }
        self.block(|p| {
            let start = p.cur.span();
            if p.is_kw("forbid") && p.cur.peek_at(1) != Tok::Arrow && p.cur.peek_at(1) != Tok::Dot {
                p.cur.bump();
                let events = p.path_list("an event to forbid")?;
                let cond = p.opt_cond()?;
                p.expect(Tok::Semi, "`;`")?;
                st.items.push(StateItem::Forbid { events, cond, span: start });
            } else if p.is_kw("impossible") && p.cur.peek_at(1) != Tok::Arrow && p.cur.peek_at(1) != Tok::Dot {
                p.cur.bump();
                let events = p.path_list("an event")?;
                p.expect(Tok::Semi, "`;`")?;
                st.items.push(StateItem::Impossible { events, span: start });
            } else {
                let event = p.path("an event, `forbid` or `impossible`")?;
                p.expect(Tok::Arrow, "`->`")?;
                let (target, target_span) = p.ident("a target state")?;
                let cond = p.opt_cond()?;
                p.expect(Tok::Semi, "`;`")?;
                let span = event.span;
                st.items.push(StateItem::Trans { event, target, target_span, cond, span });
            }
            Ok(())
        })?;
        Ok(st)
    }

    fn opt_cond(&mut self) -> PResult<Option<CondExpr>> {
        if !self.is_kw("if") {
            return Ok(None);
        }
        self.cur.bump();
        self.expect(Tok::LBracket, "`[` to open the condition")?;
        let c = self.cond_or(0)?;
        self.expect(Tok::RBracket, "`]` to close the condition")?;
        Ok(Some(c))
    }

    fn cond_or(&mut self, depth: usize) -> PResult<CondExpr> {
        let mut operands = vec![self.cond_and(depth)?];
        while self.is_kw("or") {
            self.cur.bump();
            operands.push(self.cond_and(depth)?);
        }
        Ok(if operands.len() == 1 { operands.pop().expect("one operand") } else { CondExpr::Or(operands) })
    }

    fn cond_and(&mut self, depth: usize) -> PResult<CondExpr> {
        let mut operands = vec![self.cond_unary(depth)?];
        while self.is_kw("and") {
            self.cur.bump();
            operands.push(self.cond_unary(depth)?);
        }
        Ok(if operands.len() == 1 { operands.pop().expect("one operand") } else { CondExpr::And(operands) })
    }

    fn cond_unary(&mut self, depth: usize) -> PResult<CondExpr> {
        if depth > 64 {
            return self.err("a shallower condition (nesting limit 64)");
        }
        if self.is_kw("not") {
            self.cur.bump();
            return Ok(CondExpr::Not(Box::new(self.cond_unary(depth + 1)?)));
        }
        if self.cur.at(Tok::LParen) {
            self.cur.bump();
            let c = self.cond_or(depth + 1)?;
            self.expect(Tok::RParen, "`)`")?;
            return Ok(c);
        }
        if self.is_kw("true") {
            self.cur.bump();
            return Ok(CondExpr::True);
        }
        if self.is_kw("false") {
            self.cur.bump();
            return Ok(CondExpr::False);
        }
        Ok(CondExpr::State(self.path("a state such as `Heater.on`")?))
    }

    fn instance(&mut self) -> PResult<InstanceDecl> {
        self.cur.bump();
        let (name, name_span) = self.ident("an instance name")?;
        self.expect(Tok::Colon, "`:` and the template name")?;
        let template = self.path("a template name")?;
        let mut inst = InstanceDecl { name, name_span, template, bindings: Vec::new() };
        if self.cur.at(Tok::Semi) {
            self.cur.bump();
            return Ok(inst);
        }
        self.block(|p| {
            let lhs = p.path("a namespace or binding event")?;
            p.expect(Tok::Eq, "`=`")?;
            let rhs = p.path("a module or event")?;
            p.expect(Tok::Semi, "`;`")?;
            inst.bindings.push(Binding { lhs, rhs });
            Ok(())
        })?;
        Ok(inst)
    }
}

/// The text of a string literal's contents: `\"`, `\\`, `\n` and `\t` are escapes; any other
/// backslash is kept as written, so that ST fragments can use SynTACS's `\var{…}` and `\last{…}`.
pub(super) fn unescape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut it = s.chars().peekable();
    while let Some(c) = it.next() {
        if c == '\\' {
            match it.peek() {
                Some('n') => out.push('\n'),
                Some('t') => out.push('\t'),
                Some('"') => out.push('"'),
                Some('\\') => out.push('\\'),
                _ => {
                    out.push('\\');
                    continue;
                }
            }
            it.next();
        } else {
            out.push(c);
        }
    }
    out
}

/// The byte offset in a string literal's raw contents of byte `k` of its [`unescape`]d text.
pub(super) fn raw_offset(raw: &str, k: usize) -> usize {
    let mut text = 0; // bytes of unescaped text produced so far
    let mut chars = raw.char_indices().peekable();
    while let Some((i, c)) = chars.next() {
        if text >= k {
            return i;
        }
        if c == '\\' && matches!(chars.peek(), Some((_, 'n' | 't' | '"' | '\\'))) {
            chars.next();
            text += 1;
        } else {
            text += c.len_utf8();
        }
    }
    raw.len()
}
