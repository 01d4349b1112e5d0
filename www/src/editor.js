// The CodeMirror 6 editor: highlighting and completion of the open document's language
// (`.tga`, `.sct`, `.ltl`, `.tlsf`; switched with `setKind`), line numbers, bracket matching,
// and lint diagnostics from the engine (squiggles, gutter markers) refreshed as you type.
import { basicSetup } from 'codemirror';
import { EditorView, keymap } from '@codemirror/view';
import { Compartment, EditorState, Prec } from '@codemirror/state';
import { HighlightStyle, syntaxHighlighting } from '@codemirror/language';
import { linter, lintGutter, forceLinting } from '@codemirror/lint';
import { tags as t } from '@lezer/highlight';
import { completions, languageOf } from './languages.js';

/** The language and the completion of a document kind. The completion source is made once per
 * kind: the autocompletion extension tells sources apart by identity, and a new function on
 * every lookup restarts its query forever. */
const sources = new Map();
const languageFor = (kind) => {
  if (!sources.has(kind)) sources.set(kind, [{ autocomplete: completions(kind) }]);
  const data = sources.get(kind);
  return [languageOf(kind), EditorState.languageData.of(() => data)];
};

/** Editor chrome in the page's colours, so that it follows the light/dark setting. */
const chrome = EditorView.theme({
  '&': { color: 'var(--fg)', backgroundColor: 'var(--bg)' },
  '.cm-content': { caretColor: 'var(--fg)' },
  '.cm-cursor, .cm-dropCursor': { borderLeftColor: 'var(--fg)' },
  '.cm-gutters': { backgroundColor: 'var(--panel)', color: 'var(--muted)', borderRight: '1px solid var(--line)' },
  '.cm-activeLine': { backgroundColor: 'var(--active-line)' },
  '.cm-activeLineGutter': { backgroundColor: 'var(--active-line)' },
  '&.cm-focused > .cm-scroller > .cm-selectionLayer .cm-selectionBackground, .cm-selectionBackground, ::selection': { backgroundColor: 'var(--selection)' },
  '.cm-tooltip': { backgroundColor: 'var(--panel)', color: 'var(--fg)', border: '1px solid var(--line)' },
  '.cm-panels': { backgroundColor: 'var(--panel)', color: 'var(--fg)' },
  '&.cm-focused .cm-matchingBracket': { backgroundColor: 'var(--match)', outline: '1px solid var(--accent)' },
});

const highlight = HighlightStyle.define([
  { tag: t.heading, color: 'var(--hl-section)', fontWeight: 'bold' },
  { tag: t.keyword, color: 'var(--hl-keyword)' },
  { tag: t.operatorKeyword, color: 'var(--hl-operator)' },
  { tag: t.controlKeyword, color: 'var(--edge-request)', fontWeight: 'bold' },
  { tag: t.definitionKeyword, color: 'var(--edge-reaction)', fontWeight: 'bold' },
  { tag: t.labelName, color: 'var(--edge-plan)', fontWeight: 'bold' },
  { tag: t.macroName, color: 'var(--edge-guard)' },
  { tag: [t.lineComment, t.blockComment], color: 'var(--hl-comment)', fontStyle: 'italic' },
  { tag: [t.number, t.atom], color: 'var(--hl-number)' },
  { tag: t.string, color: 'var(--hl-string)' },
  { tag: t.operator, color: 'var(--hl-operator)' },
]);

/** Byte offsets (UTF-8, as the engine reports) to string offsets (UTF-16, as CodeMirror uses). */
export function byteToCharMapper(text) {
  const starts = [];
  let bytes = 0;
  for (let i = 0; i < text.length; i++) {
    starts.push(bytes);
    const c = text.codePointAt(i);
    if (c > 0xffff) {
      bytes += 4;
      starts.push(bytes); // the low surrogate
      i++;
    } else bytes += c < 0x80 ? 1 : c < 0x800 ? 2 : 3;
  }
  starts.push(bytes);
  return (b) => {
    let lo = 0;
    let hi = starts.length - 1;
    while (lo < hi) {
      const mid = (lo + hi + 1) >> 1;
      if (starts[mid] <= b) lo = mid;
      else hi = mid - 1;
    }
    return Math.min(lo, text.length);
  };
}

/**
 * Creates the editor in `parent`. `check(text)` resolves to engine diagnostics;
 * `onDiagnostics(list, view)` receives them for the message list; `onChange(text)` on edits;
 * `onRun()` on Ctrl/Cmd+Enter.
 */
export function createEditor(parent, { doc, kind = 'tga', check, onDiagnostics, onChange, onRun }) {
  const language = new Compartment();
  const lint = linter(
    async (view) => {
      const text = view.state.doc.toString();
      let diagnostics;
      try {
        diagnostics = await check(text);
      } catch (error) {
        if (error === 'cancelled') return [];
        diagnostics = [{ severity: 'error', span: { start: 0, end: 0 }, line: 1, column: 1, message: String(error), notes: [] }];
      }
      if (view.state.doc.toString() !== text) return [];
      onDiagnostics(diagnostics, view);
      const toChar = byteToCharMapper(text);
      return diagnostics.map((d) => {
        const from = toChar(d.span.start);
        let to = toChar(d.span.end);
        if (to <= from) to = Math.min(from + 1, text.length);
        return {
          from: Math.min(from, text.length),
          to,
          severity: d.severity,
          message: [d.message, ...d.notes].join('\n'),
          source: `line ${d.line}`,
        };
      });
    },
    { delay: 250 },
  );
  const view = new EditorView({
    parent,
    state: EditorState.create({
      doc,
      extensions: [
        Prec.highest(keymap.of([{ key: 'Mod-Enter', run: () => (onRun(), true) }])),
        basicSetup,
        language.of(languageFor(kind)),
        chrome,
        EditorView.lineWrapping,
        syntaxHighlighting(highlight),
        lint,
        lintGutter(),
        EditorView.updateListener.of((u) => u.docChanged && onChange(u.state.doc.toString())),
      ],
    }),
  });
  return {
    view,
    get text() {
      return view.state.doc.toString();
    },
    set text(value) {
      view.dispatch({ changes: { from: 0, to: view.state.doc.length, insert: value }, selection: { anchor: 0 } });
      view.scrollDOM.scrollTop = 0;
    },
    relint: () => forceLinting(view),
    /** Switches the highlighting and completion to another document kind. */
    setKind(kind) {
      view.dispatch({ effects: language.reconfigure(languageFor(kind)) });
    },
    goto(line, column) {
      const l = view.state.doc.line(Math.min(Math.max(line, 1), view.state.doc.lines));
      const pos = Math.min(l.from + Math.max(column - 1, 0), l.to);
      view.dispatch({ selection: { anchor: pos }, scrollIntoView: true });
      view.focus();
    },
  };
}
