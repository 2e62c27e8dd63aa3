// Drives skillweb's page in headless Chromium (puppeteer-core, the build's node_modules through
// NODE_PATH) the way users would, over HTTPS with logins, and prints what it saw as one JSON line
// for skillweb_test.cc, which checks it against the state topic it records itself. Each user has
// a browser context of their own (their own cookies): an operator who stands the robot, runs a
// skill and stops it; a second operator whose page is refused the first page's lease; an
// observer whose controls are disabled. One page is open at a time: Chromium draws every page's
// WebGL on one software renderer here, and a page that draws starves the next one's start.
//
//   node drive_page.cjs URL CHROMIUM USERS.json [SCREENSHOT.png]
//   USERS.json: {"operator": [name, password], "second_operator": [...], "observer": [...]}
const fs = require('fs');
const puppeteer = require('puppeteer-core');

const [url, chromium, usersFile, screenshot] = process.argv.slice(2);
const users = JSON.parse(fs.readFileSync(usersFile, 'utf8'));
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

// The page in `context`, with what goes wrong on it added to `errors`.
async function openPage(context, errors) {
  const page = await context.newPage();
  if (errors) {
    page.on('console', (m) => m.type() === 'error' && errors.push(m.text()));
    page.on('requestfailed', (r) => !r.url().endsWith('/api/events') && errors.push(`failed: ${r.url()}`));
  }
  page.on('pageerror', (e) => (errors ?? []).push(String(e)));
  await page.setViewport({ width: 390, height: 844, isMobile: true, hasTouch: true, deviceScaleFactor: 2 });
  await page.goto(url, { waitUntil: 'load' });
  return page;
}

// The page showing the robot, within 20 s.
async function showsRobot(page, name) {
  try {
    await page.waitForFunction(() => window.skillweb?.ready && window.skillweb.view.tick > 0, { timeout: 20000 });
  } catch (e) {
    const seen = await page.evaluate(() => ({ ready: window.skillweb?.ready, tick: window.skillweb?.view.tick,
      link: document.getElementById('link').textContent, reply: document.getElementById('reply').textContent,
      login: document.getElementById('login-reply').textContent }));
    throw new Error(`${name}'s page did not show the robot: ${JSON.stringify(seen)}`);
  }
}

// A page of its own for `user` in a new browser context, logged in through the page's form.
async function logIn(browser, [name, password], errors) {
  const page = await openPage(await browser.createBrowserContext(), errors);
  await page.waitForSelector('#login:not([hidden])', { timeout: 10000 });
  await page.type('#login-name', name);
  await page.type('#login-password', password);
  await page.click('#login-submit');
  await showsRobot(page, name);
  return page;
}

// The text under the controls once the call `name` has an answer.
async function replyTo(page, name) {
  await page.waitForFunction((n) => {
    const t = document.getElementById('reply').textContent;
    return t.startsWith(`${n}:`);
  }, { timeout: 10000 }, name);
  return page.$eval('#reply', (e) => e.textContent);
}

async function main() {
  const browser = await puppeteer.launch({
    executablePath: chromium,
    headless: true,
    acceptInsecureCerts: true,  // skillweb's test certificate is self-signed
    // WebGL on the CPU (no GPU here); no sandbox, which needs a user namespace CI may not give.
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
  const out = { console_errors: [], samples: [] };
  try {
    // A wrong password is refused on the form (in a context of its own: a 401 is a console error).
    const stranger = await (await browser.createBrowserContext()).newPage();
    await stranger.goto(url, { waitUntil: 'load' });
    await stranger.waitForSelector('#login:not([hidden])', { timeout: 10000 });
    await stranger.type('#login-name', users.operator[0]);
    await stranger.type('#login-password', 'not-the-password');
    await stranger.click('#login-submit');
    await stranger.waitForFunction(() => document.getElementById('login-reply').textContent !== '', { timeout: 10000 });
    out.wrong_login = {
      reply: await stranger.$eval('#login-reply', (e) => e.textContent),
      main_hidden: await stranger.$eval('main', (e) => e.hidden),
    };

    let page = await logIn(browser, users.operator, out.console_errors);
    await page.waitForFunction(() => document.querySelectorAll('#skill option').length > 0, { timeout: 10000 });
    out.operator = await page.evaluate(() => ({
      who: document.getElementById('who').textContent,
      client_id: window.skillweb.session.client_id,
      stand_disabled: document.getElementById('stand').disabled,
    }));

    // A phone's screen: nothing wider than it, and the emergency stop on it.
    out.phone = await page.evaluate(() => {
      const r = document.getElementById('damp').getBoundingClientRect();
      return { overflow: document.documentElement.scrollWidth > window.innerWidth,
               estop_visible: r.width > 0 && r.top >= 0 && r.bottom <= window.innerHeight };
    });

    // Standing up moves every joint: the scene's angles, with the tick they were set from.
    await page.click('#stand');
    for (let i = 0; i < 12; ++i) {
      await sleep(120);
      out.samples.push(await page.evaluate(() => {
        const w = window.skillweb;
        return { tick: w.view.tick, joints: w.view.jointAngles(w.info.joint_names) };
      }));
    }
    await page.waitForFunction(() => window.skillweb.state.mode === 'stand', { timeout: 10000 });
    // Closing the page leaves its session, its client and so its lease in skillweb.
    const operatorContext = page.browserContext();
    await page.close();

    // A second operator's page is a second client: the first page holds the lease.
    const second = await logIn(browser, users.second_operator, out.console_errors);
    await second.click('#stand');
    out.second_operator = {
      reply: await replyTo(second, 'stand'),
      client_id: await second.evaluate(() => window.skillweb.session.client_id),
      controller: await second.evaluate(() => window.skillweb.state.controller),
    };
    await second.click('#logout');
    await second.waitForSelector('#login:not([hidden])', { timeout: 10000 });
    out.second_operator.logged_out = await second.$eval('main', (e) => e.hidden);
    await second.close();

    // An observer sees the robot; every control is disabled and says why; nothing is posted.
    const observer = await logIn(browser, users.observer, out.console_errors);
    const posts = [];
    observer.on('request', (r) => r.method() === 'POST' && posts.push(r.url()));
    await observer.click('#stand').catch(() => {});
    await observer.click('#damp').catch(() => {});
    await sleep(300);
    out.observer = await observer.evaluate(() => ({
      tick: window.skillweb.view.tick,
      who: document.getElementById('who').textContent,
      note: document.getElementById('role-note').textContent,
      controls: ['damp', 'stand', 'stop', 'run-skill', 'track'].map((id) => {
        const b = document.getElementById(id);
        return { id, disabled: b.disabled, title: b.title };
      }),
    }));
    out.observer.posts = posts;
    await observer.close();

    // The operator's page again: the session's cookie logs it in.
    page = await openPage(operatorContext, out.console_errors);
    await showsRobot(page, users.operator[0]);
    await page.waitForFunction(() => document.querySelectorAll('#skill option').length > 0, { timeout: 10000 });
    out.reopened = await page.evaluate(() => ({ login_hidden: document.getElementById('login').hidden,
                                               client_id: window.skillweb.session.client_id }));
    await sleep(1500);  // settled, so the skill's start check passes
    // The fastest skill that survived its evaluation, for 6 s.
    const skill = await page.evaluate(() => {
      const options = [...document.querySelectorAll('#skill option')].filter((o) => Number(o.dataset.survival) >= 1000);
      options.sort((a, b) => Number(b.dataset.speed) - Number(a.dataset.speed));
      return Number(options[0].value);
    });
    await page.select('#skill', String(skill));
    await page.$eval('#skill-duration', (e) => (e.value = '6'));
    await page.click('#run-skill');
    const latest = () => page.evaluate(() => window.skillweb.state);
    await page.waitForFunction((k) => window.skillweb.state.mode === 'skill' && window.skillweb.state.skill === k,
                               { timeout: 15000 }, skill);
    const first = await latest();
    await sleep(2500);
    const last = await latest();
    out.skill = { id: skill, from_tick: first.tick, to_tick: last.tick, mode: last.mode };
    if (screenshot) {
      await page.setViewport({ width: 1280, height: 1000, deviceScaleFactor: 1 });
      await sleep(600);
      await page.screenshot({ path: screenshot, fullPage: true });
    }

    await page.click('#damp');
    await page.waitForFunction(() => window.skillweb.state.mode === 'damp', { timeout: 5000 });
    out.damp = { tick: (await latest()).tick, reply: await page.$eval('#reply', (e) => e.textContent) };
  } finally {
    await browser.close();
  }
  console.log(JSON.stringify(out));
}

main().catch((e) => {
  console.error(e);
  process.exit(1);
});
