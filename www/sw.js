// Service worker: lets the playground start without a network once it has been opened.
// Network first, so that a rebuilt page is always picked up while online; every successful
// same-origin GET refreshes the cache, which answers when the network fails. On install it
// fetches what a first start needs (dist/assets.json, written by www/build.mjs, lists the
// bundles and the docs), so that the page also works offline before every view has been opened.
const CACHE = 'plcsynth';
const SHELL = ['./', 'index.html', 'style.css', 'pkg/plcsynth.js', 'pkg/plcsynth_bg.wasm'];

self.addEventListener('install', (event) => {
  event.waitUntil(
    (async () => {
      const cache = await caches.open(CACHE);
      let bundles = [];
      try {
        bundles = (await (await fetch('dist/assets.json', { cache: 'no-store' })).json()).map((f) => `dist/${f}`);
      } catch {
        // An older build without the list: the bundles are cached when first fetched.
      }
      await cache.addAll([...SHELL, ...bundles]);
      await self.skipWaiting();
    })(),
  );
});

self.addEventListener('activate', (event) => event.waitUntil(self.clients.claim()));

self.addEventListener('fetch', (event) => {
  const request = event.request;
  if (request.method !== 'GET' || new URL(request.url).origin !== self.location.origin) return;
  event.respondWith(
    (async () => {
      const cache = await caches.open(CACHE);
      try {
        const response = await fetch(request);
        if (response.ok) await cache.put(request, response.clone());
        return response;
      } catch (error) {
        const cached = (await cache.match(request, { ignoreSearch: true })) ?? (request.mode === 'navigate' ? await cache.match('./') : undefined);
        if (cached) return cached;
        throw error;
      }
    })(),
  );
});
