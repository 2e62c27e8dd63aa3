// Drives skillweb's page in headless Chromium (puppeteer-core, the build's node_modules through
// NODE_PATH) the way a user would, and prints what it saw as one JSON line for
// skillweb_test.cc, which checks it against the state topic it records itself.
//
//   node drive_page.cjs URL CHROMIUM [SCREENSHOT.png]
const puppeteer = require('puppeteer-core');

const [url, chromium, screenshot] = process.argv.slice(2);
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

async function main() {
  const browser = await puppeteer.launch({
    executablePath: chromium,
    headless: true,
    // WebGL on the CPU (no GPU here); no sandbox, which needs a user namespace CI may not give.
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
  const out = { console_errors: [], samples: [] };
  try {
    const page = await browser.newPage();
    page.on('console', (m) => m.type() === 'error' && out.console_errors.push(m.text()));
    page.on('pageerror', (e) => out.console_errors.push(String(e)));
    page.on('requestfailed', (r) => !r.url().endsWith('/api/events') && out.console_errors.push(`failed: ${r.url()}`));
    await page.setViewport({ width: 390, height: 844, isMobile: true, hasTouch: true, deviceScaleFactor: 2 });
    await page.goto(url, { waitUntil: 'load' });
    await page.waitForFunction(() => window.skillweb?.ready && window.skillweb.view.tick > 0, { timeout: 20000 });
    await page.waitForFunction(() => document.querySelectorAll('#skill option').length > 0, { timeout: 10000 });

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
