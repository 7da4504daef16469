// cncjs_run.js — drives a running CNCjs server the way its web page does (HTTP sign-in, then
// socket.io): opens the grbl port pcnc serves, loads a G-code program, starts it, waits until
// CNCjs's sender has sent every line and the machine reports Idle, then takes a headless
// Chromium screenshot of CNCjs's page (connected machine, tool path). Prints one JSON line:
// {"ok":true,"lines":N,"received":N,"state":"Idle","screenshot":PATH} or {"ok":false,"error":...}.
//
// usage: node cncjs_run.js HTTP_PORT SERIAL_PORT PROGRAM.nc SCREENSHOT.png
// Needs socket.io-client 2.x and playwright-core (tests/e2e/README.md, tools/install-deps.sh).
'use strict';
const fs = require('fs');
const http = require('http');
const io = require('socket.io-client');

const [httpPort, serialPort, programPath, screenshotPath] = process.argv.slice(2);
const base = `http://127.0.0.1:${httpPort}`;
const done = (result) => {
  process.stdout.write(JSON.stringify(result) + '\n');
  process.exit(result.ok ? 0 : 1);
};
setTimeout(() => done({ ok: false, error: 'timed out' }), 240000).unref();

function signin() {
  return new Promise((resolve, reject) => {
    const req = http.request(`${base}/api/signin`, { method: 'POST', headers: { 'Content-Type': 'application/json' } }, (res) => {
      let body = '';
      res.on('data', (c) => { body += c; });
      res.on('end', () => {
        try { resolve(JSON.parse(body).token); } catch (e) { reject(new Error(`signin: ${body}`)); }
      });
    });
    req.on('error', reject);
    req.end('{}');
  });
}

async function screenshot(token) {
  const { chromium } = require('playwright-core');
  const browser = await chromium.launch({
    executablePath: '/usr/bin/chromium',
    args: ['--headless', '--no-sandbox', '--disable-gpu', '--disable-background-networking',
      '--disable-component-update', '--no-first-run'],
  });
  try {
    const page = await browser.newPage({ viewport: { width: 1400, height: 900 } });
    // As a user does: choose the port in the Connection widget and open it (the server has
    // it open already: the page joins it and gets the loaded program for its 3D view).
    await page.goto(`${base}/`, { waitUntil: 'load', timeout: 60000 });
    await page.getByText('Choose a port').click({ timeout: 30000 });
    await page.keyboard.type(serialPort);
    await page.keyboard.press('Enter');
    await page.getByRole('button', { name: 'Open' }).click({ timeout: 10000 });
    await page.getByRole('button', { name: 'Close', exact: true }).waitFor({ timeout: 20000 });  // connected
    await page.waitForTimeout(3000);  // the 3D view draws the tool path
    await page.screenshot({ path: screenshotPath });
    return await page.evaluate(() => document.body.innerText.slice(0, 4000));
  } finally {
    await browser.close();
  }
}

(async () => {
  const token = await signin();
  const socket = io.connect(base, { query: `token=${token}`, transports: ['websocket'] });
  const program = fs.readFileSync(programPath, 'utf8');
  let total = 0, received = 0, state = '', sentAll = false, started = false, shooting = false;
  const errors = [];
  socket.on('serialport:read', (line) => { if (/^error:/.test(line) || /^ALARM:/.test(line)) errors.push(line); });
  socket.on('sender:status', (s) => { total = s.total; received = s.received; sentAll = s.total > 0 && s.received >= s.total; });
  socket.on('controller:state', (type, st) => {
    state = st && st.status ? st.status.activeState : state;
    if (started && sentAll && state === 'Idle' && !shooting) {
      shooting = true;
      const run = { lines: total, received, state };  // the run, before the page connects
      screenshot(token).then((text) => {
        done({ ok: errors.length === 0, ...run, errors, screenshot: screenshotPath,
          page_mentions_grbl: /grbl/i.test(text), page_mentions_port: text.includes(serialPort) });
      }).catch((e) => done({ ok: false, error: `screenshot: ${e.message}`, lines: total, received, state }));
    }
  });
  socket.on('connect', () => {
    socket.emit('open', serialPort, { controllerType: 'Grbl', baudrate: 115200 }, (err) => {
      if (err) return done({ ok: false, error: `open: ${err.message || err}` });
      // wait for the controller to be ready (its first status report), then load and start
      const wait = setInterval(() => {
        if (!state) return;
        clearInterval(wait);
        socket.emit('command', serialPort, 'gcode:load', 'pcnc-e2e.nc', program, {}, (e) => {
          if (e) return done({ ok: false, error: `load: ${e.message || e}` });
          started = true;
          socket.emit('command', serialPort, 'gcode:start');
        });
      }, 100);
    });
  });
  socket.on('connect_error', (e) => done({ ok: false, error: `socket: ${e.message || e}` }));
})().catch((e) => done({ ok: false, error: e.message }));
