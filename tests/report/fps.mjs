// Measures how smoothly a report page (`fem2rbd report`) plays in Debian's headless
// Chromium (software WebGL through SwiftShader, as tests/report/check.mjs): the time the
// page takes to load (until it says it is ready); the time of posing the bodies at a
// moment (`setTime`: interpolating every body's pose and issuing the draw) and of the
// frame being drawn (until its pixels can be read back), medians over 20 moments spread
// over the timeline, after one warm-up frame; then, playing from the start of the
// timeline for SECONDS of wall time (default 10), the animation frames per second and the
// longest gap between two of them. A measurement that prints figures, not a test.
//
//   node tests/report/fps.mjs REPORT.html [SECONDS]
//
// Chromium: $CHROMIUM, else /usr/bin/chromium.
import { chromium } from "playwright-core";
import path from "node:path";
import { pathToFileURL } from "node:url";

const [report, secondsArg] = process.argv.slice(2);
if (!report) {
  console.error("usage: node fps.mjs REPORT.html [SECONDS]");
  process.exit(2);
}
const seconds = Number(secondsArg ?? 10);

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
  headless: true,
  args: ["--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist", "--no-sandbox"],
});
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 900 }, deviceScaleFactor: 1 });
  const errors = [];
  page.on("pageerror", (e) => errors.push("pageerror: " + e.message));
  const t0 = Date.now();
  await page.goto(pathToFileURL(path.resolve(report)).href);
  await page.waitForFunction(() => document.documentElement.dataset.reportReady === "1", null, {
    timeout: 600000,
    polling: 200,
  });
  const loadS = (Date.now() - t0) / 1000;
  const drawn = await page.evaluate(() => {
    const r = window.fem2rbdReport;
    const gl = r.renderer.getContext();
    const px = new Uint8Array(4);
    const flush = () => gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, px);
    r.setTime(r.times[0]);
    flush();
    const pose = [];
    const draw = [];
    const [t0, t1] = [r.times[0], r.times[r.times.length - 1]];
    for (let k = 0; k < 20; k++) {
      const a = performance.now();
      r.setTime(t0 + ((k + 0.5) / 20) * (t1 - t0));
      const b = performance.now();
      flush();
      pose.push(b - a);
      draw.push(performance.now() - b);
    }
    const median = (xs) => xs.sort((x, y) => x - y)[xs.length >> 1];
    return { set_time_ms: median(pose), draw_ms: median(draw) };
  });
  const played = await page.evaluate(async (seconds) => {
    const r = window.fem2rbdReport;
    r.setTime(r.times[0]);
    document.getElementById("play").click();
    const stamps = [];
    const start = performance.now();
    await new Promise((done) => {
      function frame(now) {
        stamps.push(now);
        if (now - start < seconds * 1000 && r.state.playing) requestAnimationFrame(frame);
        else done();
      }
      requestAnimationFrame(frame);
    });
    const t = r.state.t;
    document.getElementById("play").click();
    let gap = 0;
    for (let i = 1; i < stamps.length; i++) gap = Math.max(gap, stamps[i] - stamps[i - 1]);
    const wall = (stamps[stamps.length - 1] - stamps[0]) / 1000;
    return { frames: stamps.length - 1, wall_s: wall, longest_gap_ms: gap, timeline_reached_s: t };
  }, seconds);
  console.log(
    JSON.stringify({
      report,
      load_s: loadS,
      bodies: await page.evaluate(() => window.fem2rbdReport.bodies),
      ...drawn,
      ...played,
      fps: played.frames / played.wall_s,
      errors,
    })
  );
} finally {
  await browser.close();
}
