// Share links: `#share/v1/<target>/<spec>` where <spec> is the text deflate-compressed with
// the browser's CompressionStream ('deflate-raw') and base64url-encoded (no padding).

const VERSION = 'v1';

async function pipe(bytes, stream) {
  const out = new Blob([bytes]).stream().pipeThrough(stream);
  return new Uint8Array(await new Response(out).arrayBuffer());
}

function toBase64Url(bytes) {
  let s = '';
  for (let i = 0; i < bytes.length; i += 0x8000) s += String.fromCharCode(...bytes.subarray(i, i + 0x8000));
  return btoa(s).replace(/\+/g, '-').replace(/\//g, '_').replace(/=+$/, '');
}

function fromBase64Url(text) {
  const b64 = text.replace(/-/g, '+').replace(/_/g, '/');
  const s = atob(b64 + '='.repeat((4 - (b64.length % 4)) % 4));
  return Uint8Array.from(s, (c) => c.charCodeAt(0));
}

export async function encodeShare(spec, target) {
  const packed = await pipe(new TextEncoder().encode(spec), new CompressionStream('deflate-raw'));
  return `share/${VERSION}/${encodeURIComponent(target)}/${toBase64Url(packed)}`;
}

/** Decodes a hash (without `#`); returns `{ spec, target }`, or null if it is not a share link. */
export async function decodeShare(hash) {
  const m = hash.match(/^share\/(v\d+)\/([^/]*)\/([A-Za-z0-9_-]*)$/);
  if (!m) return null;
  if (m[1] !== VERSION) throw new Error(`share link version ${m[1]} is not supported (this page reads ${VERSION})`);
  const bytes = await pipe(fromBase64Url(m[3]), new DecompressionStream('deflate-raw'));
  return { spec: new TextDecoder().decode(bytes), target: decodeURIComponent(m[2]) };
}
