// Shared set-up of the browser tests: serves www/ with python3's static server on a free
// port and drives Debian's Chromium (/usr/bin/chromium) with playwright-core.
import { spawn } from 'node:child_process';
import { mkdirSync, writeFileSync, readFileSync, existsSync, rmSync } from 'node:fs';
import { dirname, join } from 'node:path';
import { fileURLToPath } from 'node:url';
import { before, after } from 'node:test';
import { chromium } from 'playwright-core';

export const root = join(dirname(fileURLToPath(import.meta.url)), '..', '..');
export const screenshots = join(root, 'target', 'screenshots');

/** Flags from GUIDE.md: without the networking ones Chromium floods the closed network. */
const FLAGS = ['--no-sandbox', '--disable-gpu', '--disable-quic', '--no-first-run', '--disable-background-networking', '--disable-component-update', '--disable-sync'];

export async function startServer() {
  if (!existsSync(join(root, 'www', 'pkg', 'plcsynth_bg.wasm')) || !existsSync(join(root, 'www', 'dist', 'main.js'))) {
    throw new Error('www/ is not built: run `make web` (or `make test-browser`) first');
  }
  const proc = spawn('python3', ['-u', '-m', 'http.server', '--bind', '127.0.0.1', '--directory', join(root, 'www'), '0'], { stdio: ['ignore', 'pipe', 'pipe'] });
  const port = await new Promise((resolve, reject) => {
    let out = '';
    const timer = setTimeout(() => reject(new Error(`the static server did not start: ${out}`)), 10000);
    proc.stdout.on('data', (chunk) => {
      out += chunk;
      const m = out.match(/port (\d+)/);
      if (m) {
        clearTimeout(timer);
        resolve(Number(m[1]));
      }
    });
    proc.on('exit', (code) => reject(new Error(`the static server exited (${code}): ${out}`)));
  });
  proc.stderr.resume();
  return { url: `http://127.0.0.1:${port}/`, stop: () => proc.kill() };
}

/** The static server and the browser of a test file, set by [`useBrowser`] (live bindings:
 * `node --test` runs each file in a process of its own). */
export let server = null;
export let browser = null;

/** Starts the server and the browser before the file's tests and stops them after. */
export function useBrowser() {
  before(async () => {
    server = await startServer();
    browser = await launch();
  });
  after(async () => {
    await browser?.close();
    server?.stop();
  });
}

export async function launch() {
  if (!existsSync('/usr/bin/chromium')) throw new Error('/usr/bin/chromium is missing: run `make browser-setup`');
  // launch() gives every run a fresh, empty user-data-dir.
  return chromium.launch({ executablePath: '/usr/bin/chromium', headless: true, args: FLAGS });
}

/** A fresh page (own storage) at 1280×800 that fails the test on any page error or dialog.
 * The page's service worker (www/sw.js: offline start) is blocked unless `serviceWorkers` is
 * set: installing it caches every asset anew in each fresh context, CPU that the tests of
 * everything else do not need (the offline test asks for it). */
export async function newPage(browser, url, { permissions = [], serviceWorkers = false } = {}) {
  const context = await browser.newContext({
    viewport: { width: 1280, height: 800 },
    permissions,
    acceptDownloads: true,
    serviceWorkers: serviceWorkers ? 'allow' : 'block',
  });
  const page = await context.newPage();
  page.setDefaultTimeout(10000);
  page.errors = [];
  page.on('pageerror', (e) => page.errors.push(e.message));
  page.on('dialog', (d) => {
    page.errors.push(`unexpected dialog: ${d.message()}`);
    d.dismiss();
  });
  if (url) await open(page, url);
  return page;
}

export async function open(page, url) {
  await page.goto(url);
  await page.waitForSelector('body[data-engine=ready]', { timeout: 20000 });
}

export async function shot(page, name) {
  mkdirSync(screenshots, { recursive: true });
  await page.screenshot({ path: join(screenshots, `${name}.png`) });
}

export const editorText = (page) => page.evaluate(() => window.plcsynth.getText());

/** Replaces the editor's text as a paste would. */
export async function setEditorText(page, text) {
  await page.click('.cm-content');
  await page.keyboard.press('Control+A');
  await page.keyboard.press('Delete');
  await page.keyboard.insertText(text);
}

export async function runAndWait(page, timeout = 30000) {
  await page.click('#run');
  await page.waitForSelector('#verdict', { timeout });
  return page.getAttribute('#verdict', 'data-verdict');
}

export const readExample = (id) => readFileSync(join(root, 'examples', 'timed', `${id}.tga`), 'utf8');

/** Appends measurements (reported, never asserted) to target/screenshots/measurements.json.
 * The test files run in processes side by side, so the read-modify-write holds a lock (a
 * directory: its creation is atomic); a lock left by a killed run is taken after 5 s. */
export async function record(key, value) {
  mkdirSync(screenshots, { recursive: true });
  const file = join(screenshots, 'measurements.json');
  const lock = `${file}.lock`;
  const since = Date.now();
  for (;;) {
    try {
      mkdirSync(lock);
      break;
    } catch (e) {
      if (e.code !== 'EEXIST') throw e;
      if (Date.now() - since > 5000) break;
      await new Promise((resolve) => setTimeout(resolve, 20));
    }
  }
  try {
    const all = existsSync(file) ? JSON.parse(readFileSync(file, 'utf8')) : {};
    all[key] = value;
    writeFileSync(file, JSON.stringify(all, null, 2));
  } finally {
    rmSync(lock, { recursive: true, force: true });
  }
}
