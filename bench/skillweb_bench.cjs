// skillweb's cost, printed as JSON: skilld alone for S seconds, then skilld with skillweb and a
// headless Chromium on its page for S seconds. For each run skilld's tick lateness (its log at
// exit); with the browser, the delay from skillweb having a state sample to the page having it
// (p50, p99), the samples the page got per second, and skillweb's CPU use. docs/skillweb.md.
//
//   NODE_PATH=build/web/node_modules node bench/skillweb_bench.cjs [BUILD_DIR] [SECONDS]
const { spawn, execSync } = require('child_process');
const fs = require('fs');
const path = require('path');
const puppeteer = require('puppeteer-core');

const root = path.resolve(__dirname, '..');
const build = path.resolve(process.argv[2] || 'build');
const seconds = Number(process.argv[3] || 20);
const dds = { domain: String(200 + (process.pid % 30)), partition: `skillweb-bench-${process.pid}` };
const env = { ...process.env, CYCLONEDDS_URI: `file://${root}/configs/cyclonedds_loopback.xml` };
const sleep = (ms) => new Promise((r) => setTimeout(r, ms));

function start(binary, args) {
  const child = spawn(path.join(build, 'bin', binary), [...args, '--domain', dds.domain, '--partition', dds.partition],
                      { env, cwd: root });
  child.log = '';
  child.stdout.on('data', (d) => (child.log += d));
  child.stderr.on('data', (d) => (child.log += d));
  return child;
}

const skilld = () => start('skilld', ['--backend', 'sim', '--library', 'models/a1_flsd.safetensors']);

// Stops skilld with SIGINT and reads the lateness it logs as it exits.
async function stopSkilld(child) {
  const exited = new Promise((r) => child.on('exit', r));
  child.kill('SIGINT');
  await exited;
  const m = child.log.match(/lateness p50 ([\d.]+) ms, p99 ([\d.]+) ms, worst ([\d.]+) ms/);
  if (!m) throw new Error(`no lateness in skilld's log:\n${child.log}`);
  return { tick_lateness_p50_ms: Number(m[1]), tick_lateness_p99_ms: Number(m[2]), tick_lateness_worst_ms: Number(m[3]) };
}

const cpuSeconds = (pid) => {
  const fields = fs.readFileSync(`/proc/${pid}/stat`, 'utf8').split(') ')[1].split(' ');
  return (Number(fields[11]) + Number(fields[12])) / Number(execSync('getconf CLK_TCK'));  // utime + stime
};

function quantile(sorted, q) {
  return sorted[Math.min(sorted.length - 1, Math.floor(q * sorted.length))];
}

async function main() {
  const alone = skilld();
  await sleep((seconds + 2) * 1000);
  const without = await stopSkilld(alone);

  const server = skilld();
  const web = start('skillweb', ['--port', '0']);
  while (!/http:\/\/\S+\//.test(web.log)) await sleep(50);
  const url = web.log.match(/http:\/\/\S+\//)[0];
  const browser = await puppeteer.launch({
    executablePath: execSync('command -v chromium').toString().trim(),
    headless: true,
    args: ['--no-sandbox', '--use-angle=swiftshader', '--enable-unsafe-swiftshader'],
  });
  let result;
  try {
    const page = await browser.newPage();
    await page.goto(url);
    await page.waitForFunction(() => window.skillweb?.ready && window.skillweb.received > 0, { timeout: 20000 });
    await sleep(2000);
    const [received0, cpu0] = [await page.evaluate(() => window.skillweb.received), cpuSeconds(web.pid)];
    await page.evaluate(() => (window.skillweb.delays.length = 0));
    await sleep(seconds * 1000);
    const [received1, cpu1] = [await page.evaluate(() => window.skillweb.received), cpuSeconds(web.pid)];
    const delays = (await page.evaluate(() => window.skillweb.delays.slice())).sort((a, b) => a - b);
    result = {
      seconds,
      without_browser: without,
      with_browser: {
        ...(await stopSkilld(server)),
        samples_per_second: (received1 - received0) / seconds,
        delay_p50_ms: quantile(delays, 0.5),
        delay_p99_ms: quantile(delays, 0.99),
        skillweb_cpu_percent: (100 * (cpu1 - cpu0)) / seconds,
      },
    };
  } finally {
    await browser.close();
    web.kill('SIGINT');
    server.kill('SIGKILL');
  }
  console.log(JSON.stringify(result, null, 2));
}

main().catch((e) => {
  console.error(e);
  process.exit(1);
});
