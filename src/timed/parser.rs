//! Recursive-descent parser for `.tga` specifications.
//!
//! Keywords are contextual (see `lexer`). On a syntax error the parser reports it and skips to
//! the end of the statement (`;`) or of the enclosing block (`}`), so one run reports every
//! independent error of a file. Every loop consumes a token or stops, so no input can hang it.

use super::ast::*;
use super::lexer::{self, tokenize, Tok};
use crate::diag::{Diagnostics, Span};
use crate::syntax::Cursor;

/// Parses `source`, appending every syntax diagnostic to `diags`. The returned tree holds
/// everything that could be recovered.
pub fn parse(source: &str, diags: &mut Diagnostics) -> Spec {
    let tokens = report_lexical_errors(source, tokenize(source), diags);
    let mut parser = Parser { source, cur: Cursor::new(tokens), diags, spec: Spec::default() };
    parser.spec();
    parser.spec
}

/// Reports the lexer's error tokens and returns the others.
fn report_lexical_errors(source: &str, tokens: Vec<lexer::Token>, diags: &mut Diagnostics) -> Vec<Token> {
    let mut kept = Vec::with_capacity(tokens.len());
    for t in tokens {
        match t.tok {
            Tok::Error => {
                let text = &source[t.span.range()];
                diags.error(t.span, format!("unexpected character `{}`", text.escape_debug()));
            }
            Tok::UnterminatedComment => {
                diags.error(t.span, "block comment is never closed").with_note("add `*/` to close it");
            }
            _ => kept.push((t.tok, t.span)),
        }
    }
    kept
}

struct Parser<'s, 'd, 'a> {
    source: &'s str,
    cur: Cursor<Tok>,
    diags: &'d mut Diagnostics<'a>,
    spec: Spec,
}

/// How deeply parentheses and `not` may nest in a condition. Real assertions nest a few levels;
/// the bound keeps recursion (here, in the checker and in dropping the tree) far from the stack
/// limit of a wasm worker.
const MAX_COND_NESTING: usize = 64;

/// Marks a syntax error already reported; the caller recovers.
struct Reported;

type PResult<T> = Result<T, Reported>;

/// A token and its span.
type Token = (Tok, Span);

impl Parser<'_, '_, '_> {
    // ----- token access -------------------------------------------------------------------

    fn text(&self, t: Token) -> &str {
        &self.source[t.1.range()]
    }

    /// True if the next token is the identifier `word`.
    fn at_word(&self, word: &str) -> bool {
        let t = self.cur.token();
        t.0 == Tok::Ident && self.text(t) == word
    }

    fn eat_word(&mut self, word: &str) -> bool {
        if self.at_word(word) {
            self.cur.bump();
            true
        } else {
            false
        }
    }

    fn describe(&self, t: Token) -> String {
        match t.0 {
            Tok::Eof => "end of file".to_string(),
            Tok::Ident => format!("`{}`", self.text(t)),
            Tok::Int => format!("number `{}`", self.text(t)),
            _ => format!("`{}`", self.text(t)),
        }
    }

    fn error_expected(&mut self, what: &str) -> Reported {
        let t = self.cur.token();
        let found = self.describe(t);
        self.diags.error(t.1, format!("expected {what}, found {found}"));
        Reported
    }

    fn expect(&mut self, tok: Tok, what: &str) -> PResult<Token> {
        if self.cur.at(tok) {
            Ok(self.cur.bump())
        } else {
            Err(self.error_expected(what))
        }
    }

    fn expect_word(&mut self, word: &str) -> PResult<Token> {
        if self.at_word(word) {
            Ok(self.cur.bump())
        } else {
            Err(self.error_expected(&format!("`{word}`")))
        }
    }

    fn ident(&mut self, what: &str) -> PResult<Ident> {
        let t = self.expect(Tok::Ident, what)?;
        Ok(Ident { name: self.text(t).to_string(), span: t.1 })
    }

    fn int(&mut self, what: &str) -> PResult<u32> {
        let t = self.expect(Tok::Int, what)?;
        match self.text(t).parse::<u32>() {
            Ok(v) if v <= MAX_CONSTANT => Ok(v),
            _ => {
                self.diags.error(t.1, format!("number is too large (at most {MAX_CONSTANT})"));
                Err(Reported)
            }
        }
    }

    fn span_from(&self, start: Span) -> Span {
        Span::new(start.start as usize, self.cur.prev_end())
    }

    // ----- recovery -----------------------------------------------------------------------

    /// Skips to just after the next `;` of this nesting level, or to the `}` closing the current
    /// block (not consumed), whichever comes first.
    fn recover_statement(&mut self) {
        let mut depth = 0usize;
        loop {
            match self.cur.peek() {
                Tok::Eof => return,
                Tok::Semi if depth == 0 => {
                    self.cur.bump();
                    return;
                }
                Tok::RBrace if depth == 0 => return,
                Tok::LBrace => depth += 1,
                Tok::RBrace => depth -= 1,
                _ => {}
            }
            self.cur.bump();
        }
    }

    /// Parses `{ item* }` where each item is parsed by `item`; errors in one item are recovered
    /// at the next `;` or at the closing brace. Returns the span up to the closing brace.
    fn block(&mut self, what: &str, mut item: impl FnMut(&mut Self) -> PResult<()>) -> PResult<()> {
        self.expect(Tok::LBrace, &format!("`{{` to open the {what}"))?;
        loop {
            if self.cur.eat(Tok::RBrace) {
                return Ok(());
            }
            if self.cur.at(Tok::Eof) {
                self.error_expected(&format!("`}}` to close the {what}"));
                return Err(Reported);
            }
            let before = self.cur.pos();
            if item(self).is_err() {
                self.recover_statement();
            }
            if self.cur.pos() == before {
                // Nothing consumed: report once and skip the token to guarantee progress.
                let t = self.cur.bump();
                if !matches!(t.0, Tok::Semi) {
                    let found = self.describe(t);
                    self.diags.error(t.1, format!("unexpected {found} in the {what}"));
                }
            }
        }
    }

    // ----- top level ----------------------------------------------------------------------

    fn spec(&mut self) {
        while !self.cur.at(Tok::Eof) {
            let before = self.cur.pos();
            if self.section().is_err() {
                self.recover_section();
            }
            if self.cur.pos() == before {
                self.cur.bump();
            }
        }
    }

    /// After an error at the top level, skip to the next word that starts a section.
    fn recover_section(&mut self) {
        let mut depth = 0usize;
        loop {
            let t = self.cur.token();
            match t.0 {
                Tok::Eof => return,
                Tok::LBrace => depth += 1,
                Tok::RBrace => {
                    depth = depth.saturating_sub(1);
                    if depth == 0 {
                        self.cur.bump();
                        return;
                    }
                }
                Tok::Ident if depth == 0 && SECTION_WORDS.contains(&self.text(t)) => return,
                _ => {}
            }
            self.cur.bump();
        }
    }

    fn section(&mut self) -> PResult<()> {
        let t = self.cur.token();
        if t.0 == Tok::Semi {
            self.cur.bump();
            return Ok(());
        }
        if t.0 == Tok::RBrace {
            self.cur.bump();
            self.diags.warning(t.1, "unmatched `}` at the top level is ignored");
            return Ok(());
        }
        if t.0 != Tok::Ident {
            return Err(self.error_expected(
                "a section (`plant`, `assertions`, `dependencies`, `guards`, `plans`, `timeunit`, `scan` or `io`)",
            ));
        }
        match self.text(t) {
            "plant" => {
                self.cur.bump();
                self.block("plant", |p| p.component())
            }
            "assertions" => {
                self.cur.bump();
                self.block("assertions", |p| p.assertion())
            }
            "dependencies" => {
                self.cur.bump();
                self.block("dependencies", |p| p.dependency())
            }
            "guards" => {
                self.cur.bump();
                self.block("guards", |p| p.guard())
            }
            "plans" => {
                self.cur.bump();
                self.block("plans", |p| p.plan())
            }
            "io" => {
                self.cur.bump();
                self.block("io section", |p| p.io_entry())
            }
            "timeunit" => self.timeunit(),
            "scan" => self.scan(),
            _ => Err(self.error_expected(
                "a section (`plant`, `assertions`, `dependencies`, `guards`, `plans`, `timeunit`, `scan` or `io`)",
            )),
        }
    }

    fn timeunit(&mut self) -> PResult<()> {
        let decl = self.duration("the time unit")?;
        self.spec.timeunit.push(decl);
        Ok(())
    }

    fn scan(&mut self) -> PResult<()> {
        let decl = self.duration("the scan time")?;
        self.spec.scan.push(decl);
        Ok(())
    }

    /// `KEYWORD INT unit ;` for `timeunit` and `scan`.
    fn duration(&mut self, what: &str) -> PResult<TimeUnitDecl> {
        let start = self.cur.bump().1;
        let value_tok = self.cur.token();
        let value = self.int("a duration such as `100ms`")?;
        let unit = self.ident("a time unit (`ms`, `s`, `min` or `h`)")?;
        let factor = match unit.name.as_str() {
            "ms" => 1,
            "s" => 1000,
            "min" => 60_000,
            "h" => 3_600_000,
            other => {
                self.diags
                    .error(unit.span, format!("unknown time unit `{other}`"))
                    .with_note("use `ms`, `s`, `min` or `h`");
                return Err(Reported);
            }
        };
        if value == 0 {
            self.diags.error(value_tok.1, format!("{what} must be longer than zero"));
        }
        self.expect(Tok::Semi, &format!("`;` after {what}"))?;
        // At most 2^24 h, about 6·10^13 ms: no overflow. Each PLC target checks its own limits.
        Ok(TimeUnitDecl { millis: u64::from(value) * factor, span: self.span_from(start) })
    }

    // ----- plant components ---------------------------------------------------------------

    fn component(&mut self) -> PResult<()> {
        if self.cur.eat(Tok::Semi) {
            return Ok(());
        }
        let start = self.cur.span();
        let kind = self.cur.token();
        let word = if kind.0 == Tok::Ident { self.text(kind).to_string() } else { String::new() };
        match word.as_str() {
            "automaton" => {
                self.cur.bump();
                let name = self.ident("the automaton's name")?;
                let mut decl =
                    AutomatonDecl { name, clocks: Vec::new(), nodes: Vec::new(), transitions: Vec::new(), span: start };
                let res = self.block("automaton", |p| p.automaton_item(&mut decl));
                decl.span = self.span_from(start);
                self.spec.components.push(Component::Automaton(decl));
                res
            }
            "hardware" | "operator" => {
                self.cur.bump();
                let name = self.ident(&format!("the {word}'s name"))?;
                let mut states = Vec::new();
                let mut moves = Vec::new();
                let res = self.block(&word, |p| p.move_item(&mut states, &mut moves));
                let span = self.span_from(start);
                self.spec.components.push(if word == "hardware" {
                    Component::Hardware(HardwareDecl { name, states, moves, span })
                } else {
                    Component::Operator(OperatorDecl { name, states, moves, span })
                });
                res
            }
            _ => Err(self.error_expected("a component (`automaton`, `hardware` or `operator`)")),
        }
    }

    fn automaton_item(&mut self, decl: &mut AutomatonDecl) -> PResult<()> {
        if self.at_word("clocks") && self.cur.peek_at(1) == Tok::Ident {
            self.cur.bump();
            decl.clocks.extend(self.ident_list("a clock name")?);
            self.expect(Tok::Semi, "`;` after the clock list")?;
            return Ok(());
        }
        if self.at_word("nodes") && self.cur.peek_at(1) == Tok::Ident && !self.is_arrow(self.cur.peek_at(1)) {
            self.cur.bump();
            loop {
                let name = self.ident("a node name")?;
                let invariant = if self.cur.at(Tok::LBrace) { self.constraint_block()? } else { Vec::new() };
                decl.nodes.push(NodeDecl { name, invariant });
                if !self.cur.eat(Tok::Comma) {
                    break;
                }
            }
            self.expect(Tok::Semi, "`,` or `;` in the node list")?;
            return Ok(());
        }
        self.transition(decl)
    }

    fn is_arrow(&self, tok: Tok) -> bool {
        matches!(tok, Tok::Arrow | Tok::UnicodeArrow)
    }

    fn transition(&mut self, decl: &mut AutomatonDecl) -> PResult<()> {
        let start = self.cur.span();
        let from = self.ident("a transition (`from -> to ?message`), `clocks` or `nodes`")?;
        if !(self.cur.eat(Tok::Arrow) || self.cur.eat(Tok::UnicodeArrow)) {
            return Err(self.error_expected("`->`"));
        }
        let to = self.ident("the target node")?;
        let kind = match self.cur.peek() {
            Tok::Question => MessageKind::Controllable,
            Tok::Bang => MessageKind::Uncontrollable,
            Tok::Dollar => MessageKind::Synchronised,
            _ => return Err(self.error_expected("a message type `?`, `!` or `$`")),
        };
        self.cur.bump();
        let message = self.ident("a message name")?;
        let mut guard = Vec::new();
        let mut resets = Vec::new();
        let mut instant = false;
        loop {
            if self.cur.at(Tok::LBrace) {
                guard.extend(self.constraint_block()?);
            } else if self.at_word("reset") {
                self.cur.bump();
                self.expect(Tok::LBrace, "`{` before the clocks to reset")?;
                resets.extend(self.ident_list("a clock name")?);
                self.expect(Tok::RBrace, "`}` after the clocks to reset")?;
            } else if self.at_word("instant") {
                self.cur.bump();
                instant = true;
            } else {
                break;
            }
        }
        self.expect(Tok::Semi, "`;`, a guard `{…}`, `reset{…}` or `instant` after the transition")?;
        decl.transitions.push(TransitionDecl {
            from,
            to,
            kind,
            message,
            guard,
            resets,
            instant,
            span: self.span_from(start),
        });
        Ok(())
    }

    fn ident_list(&mut self, what: &str) -> PResult<Vec<Ident>> {
        let mut list = vec![self.ident(what)?];
        while self.cur.eat(Tok::Comma) {
            list.push(self.ident(what)?);
        }
        Ok(list)
    }

    /// `{ c in [a,b] and d in (0,inf) }`; `,` is accepted in place of `and` as in the thesis.
    fn constraint_block(&mut self) -> PResult<Vec<ClockConstraint>> {
        self.expect(Tok::LBrace, "`{`")?;
        let mut list = Vec::new();
        if self.cur.eat(Tok::RBrace) {
            return Ok(list);
        }
        loop {
            let clock = self.ident("a clock name")?;
            self.expect_word("in")?;
            let interval = self.interval()?;
            let span = clock.span.to(interval.span);
            list.push(ClockConstraint { clock, interval, span });
            if !(self.eat_word("and") || self.cur.eat(Tok::Comma)) {
                break;
            }
        }
        self.expect(Tok::RBrace, "`and` or `}` in the clock constraints")?;
        Ok(list)
    }

    fn interval(&mut self) -> PResult<Interval> {
        let open = self.cur.token();
        let lower_closed = match open.0 {
            Tok::LBracket => true,
            Tok::LParen => false,
            _ => return Err(self.error_expected("an interval such as `[2,4]` or `(0,inf)`")),
        };
        self.cur.bump();
        let lower = self.int("the interval's lower bound")?;
        self.expect(Tok::Comma, "`,` between the interval's bounds")?;
        let upper = if self.at_word("inf") {
            self.cur.bump();
            None
        } else {
            Some(self.int("the interval's upper bound or `inf`")?)
        };
        let close = self.cur.token();
        let upper_closed = match close.0 {
            Tok::RBracket => true,
            Tok::RParen => false,
            _ => return Err(self.error_expected("`]` or `)` to close the interval")),
        };
        self.cur.bump();
        let span = self.span_from(open.1);
        if upper.is_none() && upper_closed {
            self.diags
                .error(close.1, "an interval unbounded above must end with `)`")
                .with_note("write `[3,inf)`: no clock value equals infinity");
        }
        Ok(Interval { lower, lower_closed, upper, upper_closed, span })
    }

    fn move_item(&mut self, states: &mut Vec<Ident>, moves: &mut Vec<MoveDecl>) -> PResult<()> {
        if self.at_word("states") && self.cur.peek_at(1) == Tok::Ident {
            self.cur.bump();
            states.extend(self.ident_list("a state name")?);
            self.expect(Tok::Semi, "`,` or `;` in the state list")?;
            return Ok(());
        }
        let start = self.cur.span();
        let first = self.ident("a move (`A -> B`, `A <- B`, `A <-> B` or `A, B`) or `states`")?;
        let (shape, states_of_move) = match self.cur.peek() {
            Tok::Arrow | Tok::UnicodeArrow => {
                self.cur.bump();
                (MoveShape::Forward, vec![first, self.ident("the target state")?])
            }
            Tok::BackArrow => {
                self.cur.bump();
                (MoveShape::Backward, vec![first, self.ident("the source state")?])
            }
            Tok::BothArrow => {
                self.cur.bump();
                (MoveShape::Both, vec![first, self.ident("the other state")?])
            }
            Tok::Comma => {
                let mut list = vec![first];
                while self.cur.eat(Tok::Comma) {
                    list.push(self.ident("a state name")?);
                }
                (MoveShape::All, list)
            }
            _ => return Err(self.error_expected("`->`, `<-`, `<->` or `,`")),
        };
        let takes = if self.eat_word("takes") { Some(self.interval()?) } else { None };
        self.expect(Tok::Semi, "`;` after the move")?;
        moves.push(MoveDecl { shape, states: states_of_move, takes, span: self.span_from(start) });
        Ok(())
    }

    // ----- assertions, dependencies, guards ---------------------------------------------

    fn assertion(&mut self) -> PResult<()> {
        let start = self.cur.span();
        let not_unit = self.cur.peek_at(1) != Tok::Dot;
        let assertion = if self.at_word("never") && not_unit {
            self.cur.bump();
            let cond = self.cond(0)?;
            Assertion::Never { cond, span: self.span_from(start) }
        } else if self.at_word("always") && not_unit {
            self.cur.bump();
            let cond = self.cond(0)?;
            Assertion::Always { cond, span: self.span_from(start) }
        } else {
            let cond = self.cond(0)?;
            if self.eat_word("onlyif") {
                let requires = self.cond(0)?;
                Assertion::OnlyIf { cond, requires, span: self.span_from(start) }
            } else if self.cur.at(Tok::Semi) {
                // A bare condition describes undesired states: the thesis (4.1.4) calls
                // `x onlyif y` equivalent to `x and not y`.
                Assertion::Never { cond, span: self.span_from(start) }
            } else {
                return Err(self.error_expected("`onlyif`, `and`, `or` or `;`"));
            }
        };
        self.expect(Tok::Semi, "`;` after the assertion")?;
        self.spec.assertions.push(assertion);
        Ok(())
    }

    /// A condition; `depth` counts the enclosing parentheses and `not`s, which are the only
    /// ways to nest (chains of `and`/`or` are flat), and is bounded so that no input can
    /// overflow the parser's stack (a worker in the page has far less than a native thread).
    fn cond(&mut self, depth: usize) -> PResult<Cond> {
        let first = self.cond_and(depth)?;
        if !self.at_word("or") {
            return Ok(first);
        }
        let mut operands = vec![first];
        while self.eat_word("or") {
            operands.push(self.cond_and(depth)?);
        }
        let span = operands[0].span().to(operands[operands.len() - 1].span());
        Ok(Cond::Or { operands, span })
    }

    fn cond_and(&mut self, depth: usize) -> PResult<Cond> {
        let first = self.cond_unary(depth)?;
        if !self.at_word("and") {
            return Ok(first);
        }
        let mut operands = vec![first];
        while self.eat_word("and") {
            operands.push(self.cond_unary(depth)?);
        }
        let span = operands[0].span().to(operands[operands.len() - 1].span());
        Ok(Cond::And { operands, span })
    }

    fn cond_unary(&mut self, depth: usize) -> PResult<Cond> {
        let t = self.cur.token();
        let nests =
            t.0 == Tok::LParen || (t.0 == Tok::Ident && self.text(t) == "not" && self.cur.peek_at(1) != Tok::Dot);
        if nests && depth >= MAX_COND_NESTING {
            self.diags.error(
                t.1,
                format!("condition nested too deeply: at most {MAX_COND_NESTING} levels of parentheses and `not`"),
            );
            return Err(Reported);
        }
        if t.0 == Tok::LParen {
            self.cur.bump();
            let inner = self.cond(depth + 1)?;
            self.expect(Tok::RParen, "`)` to close the parenthesis")?;
            return Ok(inner);
        }
        if t.0 == Tok::Ident && self.cur.peek_at(1) != Tok::Dot {
            match self.text(t) {
                "not" => {
                    self.cur.bump();
                    let operand = self.cond_unary(depth + 1)?;
                    let span = self.span_from(t.1);
                    return Ok(Cond::Not { operand: Box::new(operand), span });
                }
                "true" | "false" => {
                    self.cur.bump();
                    return Ok(Cond::Const { value: self.text(t) == "true", span: t.1 });
                }
                _ => {}
            }
        }
        let unit = self.ident("a condition (`unit.node`, `not`, `(`, `true` or `false`)")?;
        self.expect(Tok::Dot, "`.` between unit and node (`unit.node`)")?;
        let node = self.ident("a node name")?;
        let prefix = self.cur.eat(Tok::Star);
        let span = self.span_from(unit.span);
        Ok(Cond::State { unit, node, prefix, span })
    }

    fn dependency(&mut self) -> PResult<()> {
        let start = self.cur.span();
        let message = self.ident("a message name")?;
        if !self.eat_word("dependson") {
            if self.at_word("depends") && self.cur.peek_at(1) == Tok::Ident && self.text(self.cur.token_at(1)) == "on" {
                self.cur.bump();
                self.cur.bump();
            } else {
                return Err(self.error_expected("`dependson`"));
            }
        }
        let mut targets = Vec::new();
        loop {
            let t = self.cur.token();
            if t.0 == Tok::Ident && self.text(t) == "time" {
                self.cur.bump();
                targets.push(DependencyTarget::Time { span: t.1 });
            } else {
                targets.push(DependencyTarget::Message { name: self.ident("`time` or a message name")? });
            }
            if !self.cur.eat(Tok::Comma) {
                break;
            }
        }
        self.expect(Tok::Semi, "`,` or `;` in the dependency")?;
        self.spec.dependencies.push(Dependency { message, targets, span: self.span_from(start) });
        Ok(())
    }

    fn guard(&mut self) -> PResult<()> {
        let start = self.cur.span();
        let cond = self.cond(0)?;
        self.expect_word("guardedby")?;
        let message = self.ident("the guarding message")?;
        self.expect(Tok::Semi, "`;` after the guard")?;
        self.spec.guards.push(StateGuard { cond, message, span: self.span_from(start) });
        Ok(())
    }

    // ----- plans --------------------------------------------------------------------------

    fn plan(&mut self) -> PResult<()> {
        if self.cur.eat(Tok::Semi) {
            return Ok(());
        }
        let start = self.expect_word("plan")?.1;
        let mut plan = Plan { clocks: Vec::new(), commands: Vec::new(), span: start };
        let res = self.block("plan", |p| p.plan_item(&mut plan));
        plan.span = self.span_from(start);
        self.spec.plans.push(plan);
        res
    }

    fn plan_item(&mut self, plan: &mut Plan) -> PResult<()> {
        if self.at_word("clocks") && self.cur.peek_at(1) == Tok::Ident && self.cur.peek_at(2) == Tok::Int {
            self.cur.bump();
            loop {
                let name = self.ident("a timeout clock name")?;
                let bound = self.int("the clock's timeout bound")?;
                let span = self.span_from(name.span);
                plan.clocks.push(PlanClock { name, bound, span });
                if !self.cur.eat(Tok::Comma) {
                    break;
                }
            }
            self.expect(Tok::Semi, "`,` or `;` in the clock list")?;
            return Ok(());
        }
        let start = self.cur.span();
        let label = if self.cur.peek() == Tok::Ident && self.cur.peek_at(1) == Tok::Colon {
            let l = self.ident("a label")?;
            self.cur.bump();
            Some(l)
        } else {
            None
        };
        let action = if self.eat_word("reset") {
            PlanAction::Reset { clocks: self.ident_list("a timeout clock name")? }
        } else if self.eat_word("waitfor") {
            let mut items = Vec::new();
            loop {
                let message = self.ident("a message name")?;
                let target = if self.cur.eat(Tok::Arrow) || self.cur.eat(Tok::UnicodeArrow) {
                    Some(self.ident("a label or `failed`")?)
                } else {
                    None
                };
                items.push(WaitItem { message, target });
                if !self.cur.eat(Tok::Comma) {
                    break;
                }
            }
            PlanAction::Waitfor { items }
        } else {
            return Err(self.error_expected("`reset`, `waitfor`, `clocks` or a label"));
        };
        self.expect(Tok::Semi, "`;` after the plan command")?;
        plan.commands.push(PlanCommand { label, action, span: self.span_from(start) });
        Ok(())
    }

    // ----- io -----------------------------------------------------------------------------

    fn io_entry(&mut self) -> PResult<()> {
        let start = self.cur.span();
        let message = self.ident("a message name")?;
        self.expect(Tok::Eq, "`=`")?;
        let mode = match self.cur.token() {
            t if t.0 == Tok::Ident && matches!(self.cur.peek_at(1), Tok::Address | Tok::Str | Tok::Ident) => {
                let mode = match self.text(t) {
                    "not" => Some(IoMode::Negated),
                    "set" => Some(IoMode::Set),
                    "reset" => Some(IoMode::Reset),
                    "pulse" => Some(IoMode::Pulse),
                    _ => None,
                };
                if mode.is_some() {
                    self.cur.bump();
                }
                mode.unwrap_or(IoMode::Default)
            }
            _ => IoMode::Default,
        };
        let t = self.cur.token();
        let target = match t.0 {
            Tok::Address => {
                self.cur.bump();
                IoTarget::Address { text: self.text(t)[1..].to_string(), span: t.1 }
            }
            Tok::Str => {
                self.cur.bump();
                let text = self.text(t);
                IoTarget::Symbol { text: text[1..text.len() - 1].to_string(), span: t.1, quoted: true }
            }
            Tok::Ident => {
                let mut text = self.ident("a symbol")?.name;
                while self.cur.eat(Tok::Dot) {
                    text.push('.');
                    text.push_str(&self.ident("a name after `.`")?.name);
                }
                IoTarget::Symbol { text, span: self.span_from(t.1), quoted: false }
            }
            _ => return Err(self.error_expected("a PLC address such as `%I0.0` or a symbol")),
        };
        self.expect(Tok::Semi, "`;` after the io entry")?;
        self.spec.io.push(IoEntry { message, mode, target, span: self.span_from(start) });
        Ok(())
    }
}

/// Constants are bounded so that zone arithmetic cannot overflow: the zones take constants and
/// differences of two constants, which must stay within the packed bounds' `±2^28`.
pub const MAX_CONSTANT: u32 = 1 << 24;
const _: () = assert!(2 * MAX_CONSTANT as i64 <= crate::zone::Bound::MAX_CONSTANT as i64);

const SECTION_WORDS: &[&str] = &["plant", "assertions", "dependencies", "guards", "plans", "timeunit", "scan", "io"];
