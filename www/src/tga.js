// The `.tga` language for CodeMirror: a small stream tokenizer mirroring src/timed/lexer.rs.
import { StreamLanguage } from '@codemirror/language';

const sections = new Set(['plant', 'assertions', 'dependencies', 'guards', 'plans', 'timeunit', 'io']);
const keywords = new Set([
  'automaton', 'hardware', 'operator', 'plan', 'nodes', 'states', 'clocks', 'reset', 'instant',
  'never', 'always', 'waitfor', 'takes', 'time', 'depends', 'dependson', 'on', 'onlyif',
  'guardedby', 'min', 'ms',
]);
const operators = new Set(['and', 'or', 'not', 'in']);
const atoms = new Set(['true', 'false', 'inf']);

export const tga = StreamLanguage.define({
  name: 'tga',
  startState: () => ({ inComment: false }),
  token(stream, state) {
    if (state.inComment) {
      if (stream.skipTo('*/')) {
        stream.match('*/');
        state.inComment = false;
      } else stream.skipToEnd();
      return 'blockComment';
    }
    if (stream.eatSpace()) return null;
    if (stream.match('//')) {
      stream.skipToEnd();
      return 'lineComment';
    }
    if (stream.match('/*')) {
      state.inComment = true;
      return 'blockComment';
    }
    if (stream.match(/^%[IQM][XBWDL]?[0-9]+(\.[0-9]+)?/)) return 'string';
    if (stream.match(/^[?!$%][A-Za-z_][A-Za-z0-9_]*/)) {
      const sigil = stream.current()[0];
      return { '?': 'controlKeyword', '!': 'definitionKeyword', $: 'labelName', '%': 'macroName' }[sigil];
    }
    if (stream.match(/^"[^"\n]*"?/)) return 'string';
    if (stream.match(/^[0-9]+/)) return 'number';
    if (stream.match(/^(->|<->|<-|→)/)) return 'operator';
    if (stream.match(/^[A-Za-z_][A-Za-z0-9_]*/)) {
      const word = stream.current();
      if (sections.has(word)) return 'heading';
      if (keywords.has(word)) return 'keyword';
      if (operators.has(word)) return 'operatorKeyword';
      if (atoms.has(word)) return 'atom';
      return 'variableName';
    }
    if (stream.match(/^[{}()[\]]/)) return 'bracket';
    stream.next();
    return 'punctuation';
  },
  languageData: { commentTokens: { line: '//', block: { open: '/*', close: '*/' } }, closeBrackets: { brackets: ['(', '[', '{'] } },
});
