// The background jobs' Web Worker (src/app/jobs.rs, docs/background-jobs.md): the core
// compiled to wasm (interpolab-worker, src/worker_main.rs). Used instead of Trunk's loader
// shim so that the page can post a job the moment it has one: a message that arrives before
// the wasm has installed its handler is kept here and handed to it once it has. Without
// this the page had to wait for the worker's "ready", which on a freshly opened page sits
// behind the page's first frames (0.3-1 s).
var early = [];
self.onmessage = function (e) { early.push(e.data); };
importScripts("./interpolab-worker.js");
wasm_bindgen("./interpolab-worker_bg.wasm").then(function () {
  // main() has installed the real handler (and said "ready"): the early messages, in order.
  var kept = early;
  early = null;
  kept.forEach(function (data) { self.dispatchEvent(new MessageEvent("message", { data: data })); });
}, function (e) {
  // Tell the page, which then runs its job itself (a failure is not an error event).
  self.postMessage("failed\nthe worker's wasm did not start: " + e);
});
