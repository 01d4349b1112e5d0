// Document kinds and their engines, shared by the page and the engine worker (which must not
// load the editor's languages).

/** The engine of a document kind: `tga` timed games, `sct` supervisory control, `ltl` and
 * `tlsf` LTL synthesis. */
export const engineOf = (kind) => ({ tga: 'timed', sct: 'sct', ltl: 'ltl', tlsf: 'ltl' })[kind] ?? 'timed';
