// Opens a page in headless Chromium in real time (not --virtual-time-budget, whose clock
// stands still while JavaScript runs: a benchmark would time 0 ms) and prints the text of
// its #result element once the page fills it. Drives Chromium over its DevTools pipe
// (--remote-debugging-pipe: JSON messages on fds 3 and 4), so it needs only Node, which
// Debian's emscripten already depends on.  Usage: node chromium_page.js URL [timeout_s]
'use strict';
const { spawn } = require('child_process');
const url = process.argv[2], timeout = 1000 * (Number(process.argv[3]) || 120);
const chrome = spawn('chromium', ['--headless=new', '--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader',
  '--allow-file-access-from-files', '--remote-debugging-pipe', 'about:blank'],
  { stdio: ['ignore', 'ignore', 'ignore', 'pipe', 'pipe'] });
const toChrome = chrome.stdio[3], fromChrome = chrome.stdio[4];
const waiting = new Map();
let next = 0, pending = '';
function send(method, params, sessionId) {
  const msg = { id: ++next, method, params: params || {} };
  if (sessionId) msg.sessionId = sessionId;
  toChrome.write(JSON.stringify(msg) + '\0');
  return new Promise((resolve) => waiting.set(msg.id, resolve));
}
fromChrome.on('data', (data) => {
  pending += data.toString();
  for (let end; (end = pending.indexOf('\0')) >= 0; pending = pending.slice(end + 1)) {
    const m = JSON.parse(pending.slice(0, end));
    if (m.id && waiting.has(m.id)) { waiting.get(m.id)(m); waiting.delete(m.id); }
  }
});
function finish(text, code) { console.log(text); chrome.kill(); process.exit(code); }
(async () => {
  const target = await send('Target.createTarget', { url });
  const session = await send('Target.attachToTarget', { targetId: target.result.targetId, flatten: true });
  const poll = "new Promise(r => { const f = () => { const e = document.getElementById('result');" +
               " if (e && e.textContent) r(e.textContent); else setTimeout(f, 50); }; f(); })";
  // The first evaluation can land in about:blank's context, destroyed when the page
  // commits: ask again until the page's own context answers.
  for (;;) {
    const v = await send('Runtime.evaluate', { expression: poll, awaitPromise: true, returnByValue: true },
                         session.result.sessionId);
    if (v.result && v.result.result) finish(v.result.result.value, 0);
    await new Promise((r) => setTimeout(r, 100));
  }
})();
setTimeout(() => finish('timeout after ' + timeout / 1000 + ' s', 1), timeout);
