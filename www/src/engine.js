// Talks to an engine worker with promises. `cancel()` terminates the worker at once and
// starts a fresh one, so a long search can never hang the page.

export class Engine {
  constructor(name) {
    this.name = name;
    this.nextId = 1;
    this.pending = new Map();
    this.generation = 0;
    this.start();
  }

  start() {
    this.generation += 1;
    this.worker = new Worker(new URL('./worker.js', import.meta.url), { type: 'module', name: this.name });
    this.worker.onmessage = ({ data }) => this.receive(data);
    this.worker.onerror = (event) => {
      event.preventDefault();
      this.failAll(`the engine worker failed: ${event.message || 'could not start'}`);
      this.restart();
    };
  }

  restart() {
    this.worker.terminate();
    this.start();
  }

  receive(data) {
    const call = this.pending.get(data.id);
    if (!call) return;
    if ('progress' in data) return call.onProgress?.(data.progress, data.elapsed);
    if ('compiled' in data) return call.onCompiled?.(data.compiled.automata, data.compiled.warnings);
    this.pending.delete(data.id);
    if (data.ok) call.resolve(data.value);
    else {
      call.reject(data.error);
      if (data.poisoned) this.restart();
    }
  }

  failAll(reason) {
    for (const call of this.pending.values()) call.reject(reason);
    this.pending.clear();
  }

  /** Sends a request; `handlers` may hold onProgress and onCompiled. */
  call(op, payload = {}, handlers = {}) {
    const id = this.nextId++;
    return new Promise((resolve, reject) => {
      this.pending.set(id, { resolve, reject, ...handlers });
      this.worker.postMessage({ id, op, ...payload });
    });
  }

  /** Stops whatever runs: the worker is replaced, pending calls reject with `cancelled`. */
  cancel() {
    this.failAll('cancelled');
    this.restart();
  }
}
