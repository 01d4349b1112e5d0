// The editor's languages, one per document kind: `.tga` (timed games), `.sct` (supervisory
// control), `.ltl` (G4LTL's lines) and `.tlsf` (SYNTCOMP). Small stream tokenizers mirroring the
// engines' lexers over one C-like base, and completion of the names the document declares.
import { StreamLanguage } from '@codemirror/language';

// A C-like tokenizer: line and block comments, strings, numbers with units, and words classed
// by `classify(word, stream)`.
function cLike(name, classify, { extra } = {}) {
  return StreamLanguage.define({
    name,
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
      const special = extra?.(stream);
      if (special) return special;
      if (stream.match(/^"([^"\\\n]|\\.)*"?/)) return 'string';
      if (stream.match(/^[0-9]+(\.[0-9]+)?([eE][+-]?[0-9]+)?(ms|s|m|h)?/)) return 'number';
      if (stream.match(/^[A-Za-z_][A-Za-z0-9_]*/)) return classify(stream.current(), stream) ?? 'variableName';
      if (stream.match(/^(<->|->|<-|→|&&|\|\||<=|>=|==|!=|\[\]|<>)/)) return 'operator';
      if (stream.match(/^[{}()[\]]/)) return 'bracket';
      stream.next();
      return 'punctuation';
    },
    languageData: { commentTokens: { line: '//', block: { open: '/*', close: '*/' } }, closeBrackets: { brackets: ['(', '[', '{', '"'] } },
  });
}

// `.tga` (src/timed/lexer.rs): sections, keywords, `?` requests, `!` reactions, `$` plan steps,
// `%` state guards and PLC addresses.
const tgaSections = new Set(['plant', 'assertions', 'dependencies', 'guards', 'plans', 'timeunit', 'io']);
const tgaKeywords = new Set([
  'automaton', 'hardware', 'operator', 'plan', 'nodes', 'states', 'clocks', 'reset', 'instant',
  'never', 'always', 'waitfor', 'takes', 'time', 'depends', 'dependson', 'on', 'onlyif',
  'guardedby', 'min', 'ms', 'scan', 'set',
]);
const tgaOperators = new Set(['and', 'or', 'not', 'in']);
const sigilTag = { '?': 'controlKeyword', '!': 'definitionKeyword', $: 'labelName', '%': 'macroName' };

export const tga = cLike(
  'tga',
  (word) => {
    if (tgaSections.has(word)) return 'heading';
    if (tgaKeywords.has(word)) return 'keyword';
    if (tgaOperators.has(word)) return 'operatorKeyword';
    if (word === 'true' || word === 'false' || word === 'inf') return 'atom';
    return null;
  },
  {
    extra(stream) {
      if (stream.match(/^%[IQM][XBWDL]?[0-9]+(\.[0-9]+)?/)) return 'string';
      if (stream.match(/^[?!$%][A-Za-z_][A-Za-z0-9_]*/)) return sigilTag[stream.current()[0]];
      return null;
    },
  },
);

const sctItems = new Set(['module', 'event', 'timer', 'plant', 'spec', 'template', 'instance']);
const sctKeywords = new Set([
  'state', 'alphabet', 'forbid', 'if', 'selfloops', 'impossible', 'detect', 'rising', 'falling', 'edge', 'cyclic',
  'executed', 'reset', 'on', 'denial', 'accept', 'duration', 'start', 'stop', 'of', 'with',
]);
const sctKinds = new Set(['controllable', 'uncontrollable', 'enforceable']);
const sctOperators = new Set(['and', 'or', 'not']);

export const sct = cLike('sct', (word) => {
  if (sctItems.has(word)) return 'heading';
  if (sctKinds.has(word)) return 'definitionKeyword';
  if (sctKeywords.has(word)) return 'keyword';
  if (sctOperators.has(word)) return 'operatorKeyword';
  return null;
});

const g4ltlDeclarations = new Set(['INPUT', 'OUTPUT', 'TIMER', 'ASSUME', 'REAL', 'INT']);
const g4ltlTemporal = new Set(['ALWAYS', 'EVENTUALLY', 'NEXT', 'UNTIL', 'G', 'F', 'X', 'U', 'R', 'V', 'W', 'WHENEVER', 'THEN', 'FOR']);

export const g4ltl = cLike('ltl', (word) => {
  if (g4ltlDeclarations.has(word)) return 'heading';
  if (g4ltlTemporal.has(word)) return 'keyword';
  if (word === 'true' || word === 'false' || word === 'TRUE' || word === 'FALSE') return 'atom';
  return null;
});

const tlsfSections = new Set(['INFO', 'GLOBAL', 'MAIN', 'PARAMETERS', 'DEFINITIONS', 'INPUTS', 'OUTPUTS', 'INITIALLY', 'PRESET', 'REQUIRE', 'REQUIREMENTS', 'ASSUME', 'ASSUMPTIONS', 'ASSERT', 'INVARIANTS', 'GUARANTEE', 'GUARANTEES']);
const tlsfInfo = new Set(['TITLE', 'DESCRIPTION', 'SEMANTICS', 'TARGET', 'TAGS', 'Mealy', 'Moore', 'Strict', 'Finite']);
const tlsfTemporal = new Set(['G', 'F', 'X', 'U', 'R', 'W', 'MUL', 'DIV', 'MOD', 'PLUS', 'MINUS', 'SIZEOF']);

export const tlsf = cLike('tlsf', (word) => {
  if (tlsfSections.has(word)) return 'heading';
  if (tlsfInfo.has(word)) return 'definitionKeyword';
  if (tlsfTemporal.has(word)) return 'keyword';
  if (word === 'true' || word === 'false') return 'atom';
  return null;
});

/** Names the document declares, for completion (a cheap scan of the text, not a parse). */
const declarations = {
  tga: [/\b(?:automaton|operator|hardware|plan)\s+([A-Za-z_]\w*)/g, /\bnodes\s+([^;]+);/g, /\bclocks\s+([^;]+);/g, /[?!$]([A-Za-z_]\w*)/g],
  sct: [/\b(?:event|timer|plant|spec|template|module)\s+([A-Za-z_]\w*)/g, /\bstate\s+([A-Za-z_]\w*)/g],
  ltl: [/\b(?:INPUT|OUTPUT|TIMER|REAL|INT)\s+([^\n]+)/g],
  tlsf: [/\b(?:INPUTS|OUTPUTS)\s*\{([^}]*)\}/g, /^\s*([A-Za-z_]\w*)\s*(?:\(|=)/gm],
};

export function declaredNames(kind, text) {
  const names = new Set();
  // Comments declare nothing (a header saying "the event offers…" names no event `offers`).
  text = text.replace(/\/\*[\s\S]*?\*\//g, ' ').replace(/\/\/[^\n]*/g, ' ');
  for (const re of declarations[kind] ?? []) {
    for (const m of text.matchAll(re)) {
      for (const word of m[1].matchAll(/[A-Za-z_][A-Za-z0-9_]*/g)) names.add(word[0]);
    }
  }
  return [...names];
}

const keywordLists = {
  tga: ['plant', 'automaton', 'hardware', 'operator', 'nodes', 'clocks', 'assertions', 'dependencies', 'guards', 'plans', 'plan', 'never', 'always', 'waitfor', 'takes', 'dependson', 'guardedby', 'reset', 'instant', 'timeunit', 'scan'],
  sct: [...sctItems, ...sctKinds, ...sctKeywords],
  ltl: [...g4ltlDeclarations, 'ALWAYS', 'EVENTUALLY', 'NEXT', 'UNTIL', 'WHENEVER', 'THEN', 'FOR'],
  tlsf: [...tlsfSections, ...tlsfInfo],
};

/** The completion source of `kind`: declared names and keywords. */
export function completions(kind) {
  return (context) => {
    const word = context.matchBefore(/[A-Za-z_][A-Za-z0-9_]*/);
    if (!word || (word.from === word.to && !context.explicit)) return null;
    const text = context.state.doc.toString();
    const names = declaredNames(kind, text).map((label) => ({ label, type: 'variable' }));
    const keywords = (keywordLists[kind] ?? []).map((label) => ({ label, type: 'keyword' }));
    return { from: word.from, options: [...names, ...keywords], validFor: /^[A-Za-z_][A-Za-z0-9_]*$/ };
  };
}

/** The CodeMirror language of a document kind. */
export function languageOf(kind) {
  return { tga, sct, ltl: g4ltl, tlsf }[kind] ?? tga;
}

export { engineOf } from './kinds.js';

/** What a kind is called in menus. */
export const kindLabel = { tga: 'Timed game (.tga)', sct: 'Supervisory control (.sct)', ltl: 'LTL, G4LTL lines (.ltl)', tlsf: 'LTL, TLSF (.tlsf)' };
export const engineLabel = { timed: 'Timed games', sct: 'Supervisory control', ltl: 'LTL synthesis' };
