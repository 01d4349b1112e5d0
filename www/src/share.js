// Share links: `#share/v2/<kind>/<name>/<target>/<spec>` where <kind> is the document kind
// (`tga`, `sct`, `ltl`, `tlsf`), <name> the document's name (an example id or the user's),
// <target> the code target shown, and <spec> the text deflate-compressed with the browser's
// CompressionStream ('deflate-raw') and base64url-encoded (no padding). Links of version 1
// (`#share/v1/<target>/<spec>`, timed games only) are still read.
//
// A link comes from anywhere, so decoding is defensive (fuzzed by fuzz/share/fuzz.mjs, see
// docs/fuzzing.md): the inflated text is bounded by MAX_SPEC_BYTES, read chunk by chunk and
// cancelled past it, so that a deflate bomb cannot freeze the tab; every malformed link is
// rejected with an Error that says what is wrong.

const VERSION = 'v2';
const KINDS = ['tga', 'sct', 'ltl', 'tlsf'];

/** Largest specification a link may carry, in UTF-8 bytes (the largest example has 16 KB). */
export const MAX_SPEC_BYTES = 1 << 20;

/** The error of an unreadable share link; its message completes "This share link cannot be read: …". */
export class ShareError extends Error {
  constructor(message) {
    super(message);
    this.name = 'ShareError';
  }
}

async function compress(bytes) {
  const out = new Blob([bytes]).stream().pipeThrough(new CompressionStream('deflate-raw'));
  return new Uint8Array(await new Response(out).arrayBuffer());
}

/** Inflates `bytes`, stopping with an error once more than `limit` bytes come out. */
async function inflateBounded(bytes, limit) {
  const reader = new Blob([bytes]).stream().pipeThrough(new DecompressionStream('deflate-raw')).getReader();
  const chunks = [];
  let size = 0;
  try {
    for (;;) {
      const { done, value } = await reader.read();
      if (done) break;
      size += value.length;
      if (size > limit) {
        reader.cancel().catch(() => {});
        throw new ShareError(`the specification is larger than ${limit} bytes`);
      }
      chunks.push(value);
    }
  } catch (error) {
    if (error instanceof ShareError) throw error;
    throw new ShareError('the data is damaged (not deflate-compressed text)');
  }
  const out = new Uint8Array(size);
  let at = 0;
  for (const c of chunks) {
    out.set(c, at);
    at += c.length;
  }
  return out;
}

function toBase64Url(bytes) {
  let s = '';
  for (let i = 0; i < bytes.length; i += 0x8000) s += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
  return btoa(s).replace(/\+/g, '-').replace(/\//g, '_').replace(/=+$/, '');
}

function fromBase64Url(text) {
  // Unpadded base64 never leaves one character in the last group of four.
  if (text.length % 4 === 1) throw new ShareError('the data is cut off (not base64url)');
  const b64 = text.replace(/-/g, '+').replace(/_/g, '/');
  const s = atob(b64 + '='.repeat((4 - (b64.length % 4)) % 4));
  return Uint8Array.from(s, (c) => c.charCodeAt(0));
}

export async function encodeShare(spec, target, kind = 'tga', name = '') {
  const text = new TextEncoder().encode(spec);
  if (text.length > MAX_SPEC_BYTES) {
    throw new ShareError(`the specification is larger than ${MAX_SPEC_BYTES} bytes`);
  }
  if (!KINDS.includes(kind)) throw new ShareError(`unknown document kind ${kind}`);
  const part = (s) => encodeURIComponent(s).replace(/%20/g, '+');
  return `share/${VERSION}/${kind}/${part(name)}/${part(target)}/${toBase64Url(await compress(text))}`;
}

/** A URI component of a link; `what` names it in the error. */
function component(text, what) {
  try {
    return decodeURIComponent(text.replace(/\+/g, '%20'));
  } catch {
    throw new ShareError(`the ${what} is not a valid URI component`);
  }
}

/**
 * Decodes a hash (without `#`); returns `{ spec, target, kind, name }`, or null if it is not a
 * share link. Throws a ShareError for a share link that cannot be read.
 */
export async function decodeShare(hash) {
  if (!hash.startsWith('share/')) return null;
  let kind = 'tga';
  let name = '';
  let target;
  let data;
  const v1 = hash.match(/^share\/v1\/([^/]*)\/([A-Za-z0-9_-]*)$/);
  const v2 = hash.match(/^share\/v2\/([^/]*)\/([^/]*)\/([^/]*)\/([A-Za-z0-9_-]*)$/);
  if (v1) {
    target = component(v1[1], 'target');
    data = v1[2];
  } else if (v2) {
    kind = component(v2[1], 'document kind');
    if (!KINDS.includes(kind)) throw new ShareError(`the document kind ${JSON.stringify(kind.slice(0, 20))} is unknown (${KINDS.join(', ')})`);
    name = component(v2[2], 'name').slice(0, 200);
    target = component(v2[3], 'target');
    data = v2[4];
  } else {
    const version = hash.match(/^share\/(v\d+)\//)?.[1];
    if (version && version !== 'v1' && version !== VERSION) throw new ShareError(`version ${version} is not supported (this page reads v1 and ${VERSION})`);
    throw new ShareError('the link is malformed (expected #share/v2/<kind>/<name>/<target>/<data>)');
  }
  // The packed text is at most as long as the text it inflates to, plus a little.
  if (data.length > (MAX_SPEC_BYTES / 3) * 4 + 1024) throw new ShareError('the link is too long');
  const bytes = await inflateBounded(fromBase64Url(data), MAX_SPEC_BYTES);
  let spec;
  try {
    spec = new TextDecoder('utf-8', { fatal: true }).decode(bytes);
  } catch {
    throw new ShareError('the specification is not UTF-8 text');
  }
  return { spec, target, kind, name };
}
