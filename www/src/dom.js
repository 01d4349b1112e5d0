// Tiny DOM helpers.
export const $ = (selector, root = document) => root.querySelector(selector);

/** Creates an element: h('li', { class: 'x', onclick }, 'text', child). */
export function h(tag, attrs = {}, ...children) {
  const el = document.createElement(tag);
  for (const [k, v] of Object.entries(attrs)) {
    if (v === null || v === undefined || v === false) continue;
    if (k.startsWith('on')) el.addEventListener(k.slice(2), v);
    else if (k === 'class') el.className = v;
    else el.setAttribute(k, v === true ? '' : v);
  }
  el.append(...children.flat().filter((c) => c !== null && c !== undefined && c !== false));
  return el;
}

let toastTimer = 0;
/** A message at the bottom; `action` ({ label, run }) adds a button that runs it and closes. */
export function toast(message, ms = 4000, action = null) {
  const el = $('#toast');
  el.replaceChildren(message);
  if (action) {
    el.append(' ', h('button', { class: 'toast-action', onclick: () => ((el.hidden = true), action.run()) }, action.label));
  }
  el.hidden = false;
  clearTimeout(toastTimer);
  toastTimer = setTimeout(() => (el.hidden = true), ms);
}

export const fmtInt = (n) => Number(n).toLocaleString('en');
export const fmtMs = (ms) => (ms < 1000 ? `${ms.toFixed(0)} ms` : `${(ms / 1000).toFixed(2)} s`);

/** A link that acts in the page: a real `href`, so that Tab reaches it and Enter follows it,
 * with the navigation replaced by `act()`. */
export function actionLink(text, act, attrs = {}) {
  return h('a', { href: '#', ...attrs, onclick: (event) => (event.preventDefault(), act()) }, text);
}
