// Firefox driven through Marionette, its own remote protocol (length-prefixed JSON over TCP, what
// geckodriver speaks), with only Node's standard library: playwright-core drives Firefox through WebDriver
// BiDi commands that Debian's Firefox ESR does not have. Offers the part of playwright's Page that
// viewer_browser_test.mjs uses: evaluate, waitForFunction, title, mouse.move, fill, press, screenshot.
import { spawn } from 'node:child_process';
import { existsSync, readFileSync, writeFileSync } from 'node:fs';
import { connect } from 'node:net';
import { join } from 'node:path';

const sleep = (ms) => new Promise((resolve) => setTimeout(resolve, ms));

class Connection {
  constructor(socket) {
    this.socket = socket;
    this.buffer = Buffer.alloc(0);
    this.waiting = new Map();
    this.next = 1;
    this.handshake = new Promise((resolve) => { this.onHandshake = resolve; });
    socket.on('data', (chunk) => this.receive(chunk));
  }

  // Messages are "<byte length>:<JSON>"; the first is the server's greeting, then [1, id, error, result].
  receive(chunk) {
    this.buffer = Buffer.concat([this.buffer, chunk]);
    for (;;) {
      const colon = this.buffer.indexOf(':');
      if (colon < 0) return;
      const length = Number(this.buffer.subarray(0, colon).toString());
      if (this.buffer.length < colon + 1 + length) return;
      const message = JSON.parse(this.buffer.subarray(colon + 1, colon + 1 + length).toString());
      this.buffer = this.buffer.subarray(colon + 1 + length);
      if (!Array.isArray(message)) { this.onHandshake(message); continue; }
      const [, id, error, result] = message;
      const { resolve, reject, name } = this.waiting.get(id);
      this.waiting.delete(id);
      if (error) reject(new Error(`${name}: ${error.error}: ${error.message}`)); else resolve(result);
    }
  }

  send(name, parameters = {}) {
    const id = this.next++;
    const text = JSON.stringify([0, id, name, parameters]);
    this.socket.write(`${Buffer.byteLength(text)}:${text}`);
    return new Promise((resolve, reject) => this.waiting.set(id, { resolve, reject, name }));
  }
}

// Starts Firefox (a window: run under an X server) on a fresh profile whose Marionette port is chosen by
// Firefox and written to the profile's MarionetteActivePort file.
export async function launchFirefox({ executable, profile, width, height }) {
  writeFileSync(join(profile, 'user.js'), [
    ['marionette.port', 0], ['browser.shell.checkDefaultBrowser', false],
    ['datareporting.policy.dataSubmissionEnabled', false], ['browser.aboutwelcome.enabled', false],
    ['browser.startup.homepage_override.mstone', '"ignore"'], ['startup.homepage_welcome_url', '"about:blank"'],
    ['browser.startup.page', 0], ['app.update.disabledForTesting', true], ['toolkit.telemetry.reportingpolicy.firstRun', false],
  ].map(([k, v]) => `user_pref("${k}", ${v});\n`).join(''));
  const child = spawn(executable, ['--marionette', '--no-remote', '--profile', profile, 'about:blank'],
                      { stdio: 'ignore' });
  const portFile = join(profile, 'MarionetteActivePort');
  for (let waited = 0; !existsSync(portFile) || !readFileSync(portFile, 'utf8').trim(); waited += 100) {
    if (waited > 60000 || child.exitCode !== null) throw new Error('Firefox did not open its Marionette port');
    await sleep(100);
  }
  const port = Number(readFileSync(portFile, 'utf8').trim());
  const socket = connect(port, '127.0.0.1');
  await new Promise((resolve, reject) => { socket.once('connect', resolve); socket.once('error', reject); });
  const connection = new Connection(socket);
  await connection.handshake;
  await connection.send('WebDriver:NewSession', { capabilities: { alwaysMatch: { pageLoadStrategy: 'normal' } } });
  await connection.send('WebDriver:SetWindowRect', { x: 0, y: 0, width, height });
  return new FirefoxPage(connection, child, socket);
}

class FirefoxPage {
  constructor(connection, child, socket) {
    this.connection = connection;
    this.child = child;
    this.socket = socket;
    this.mouse = { move: (x, y) => this.pointer(x, y) };
  }

  goto(url) { return this.connection.send('WebDriver:Navigate', { url }); }

  async title() { return (await this.connection.send('WebDriver:GetTitle')).value; }

  // fn is sent as source, as playwright does: it may use only its argument and the page's globals.
  async evaluate(fn, arg) {
    const result = await this.connection.send('WebDriver:ExecuteScript', {
      script: `return (${fn.toString()})(arguments[0]);`, args: [arg === undefined ? null : arg],
    });
    return result.value;
  }

  async waitForFunction(fn, arg, { timeout = 30000 } = {}) {
    for (const start = Date.now(); Date.now() - start < timeout; await sleep(50))
      if (await this.evaluate(fn, arg)) return;
    throw new Error(`waitForFunction timed out after ${timeout} ms`);
  }

  pointer(x, y) {
    return this.connection.send('WebDriver:PerformActions', {
      actions: [{ type: 'pointer', id: 'mouse', parameters: { pointerType: 'mouse' },
                  actions: [{ type: 'pointerMove', x: Math.round(x), y: Math.round(y), origin: 'viewport', duration: 0 }] }],
    });
  }

  async element(selector) {
    const found = await this.connection.send('WebDriver:FindElement', { using: 'css selector', value: selector });
    return Object.values(found.value ?? found)[0];
  }

  async fill(selector, text) {
    const id = await this.element(selector);
    await this.connection.send('WebDriver:ElementClear', { id });
    await this.connection.send('WebDriver:ElementSendKeys', { id, text });
  }

  async press(selector, key) {
    if (key !== 'Enter') throw new Error(`press: only Enter is supported, not ${key}`);
    await this.connection.send('WebDriver:ElementSendKeys', { id: await this.element(selector), text: '\uE007' });
  }

  async screenshot({ path }) {
    const shot = await this.connection.send('WebDriver:TakeScreenshot', { full: false });
    writeFileSync(path, Buffer.from(shot.value, 'base64'));
  }

  async close() {
    await this.connection.send('Marionette:Quit', { flags: ['eForceQuit'] }).catch(() => {});
    this.socket.destroy();
    if (this.child.exitCode === null) {
      await Promise.race([new Promise((resolve) => this.child.once('exit', resolve)), sleep(10000)]);
      if (this.child.exitCode === null) this.child.kill('SIGKILL');
    }
  }
}
