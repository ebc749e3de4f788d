// Opens an ensemble report page (`fem2rbd report ENSEMBLE_DIR`) in Debian's headless
// Chromium through playwright-core, reads what it shows and takes one screenshot of its
// 3-D view. Prints one JSON object on stdout for tests/it/report/ensemble.rs.
//
//   node tests/report/check_ensemble.mjs REPORT.html SCREENSHOT.png
import { chromium } from "playwright-core";
import path from "node:path";
import { pathToFileURL } from "node:url";

const [report, shot] = process.argv.slice(2);
if (!report || !shot) {
  console.error("usage: node check_ensemble.mjs REPORT.html SCREENSHOT.png");
  process.exit(2);
}
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
  headless: true,
  args: ["--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist", "--no-sandbox"],
});
const out = { errors: [] };
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 900 }, deviceScaleFactor: 1 });
  page.on("pageerror", (e) => out.errors.push("pageerror: " + e.message));
  page.on("console", (m) => {
    if (m.type() === "error") out.errors.push("console.error: " + m.text());
  });
  await page.route(/^(?!file:).*/, (route) => {
    out.errors.push("network request: " + route.request().url());
    return route.abort();
  });
  await page.goto(pathToFileURL(path.resolve(report)).href);
  await page.waitForFunction(() => document.documentElement.dataset.reportReady === "1", null, {
    timeout: 60000,
  });
  await page.locator("#view").screenshot({ path: shot });
  // Per member: instances drawn, and the world box of the drawn active bodies (each
  // instance's unit cube through its matrix).
  Object.assign(
    out,
    await page.evaluate(() => {
      const r = window.fem2rbdReport;
      const T = window.THREE;
      const passive = JSON.parse(document.getElementById("report-data").textContent).bodies.passive;
      const m = new T.Matrix4();
      const v = new T.Vector3();
      const members = r.meshes.map((mesh) => {
        const lo = [Infinity, Infinity, Infinity];
        const hi = [-Infinity, -Infinity, -Infinity];
        for (let i = 0; i < mesh.count; i++) {
          if (passive[i]) continue;
          mesh.getMatrixAt(i, m);
          for (let c = 0; c < 8; c++) {
            v.set(c & 1 ? 0.5 : -0.5, c & 2 ? 0.5 : -0.5, c & 4 ? 0.5 : -0.5).applyMatrix4(m);
            for (let k = 0; k < 3; k++) {
              lo[k] = Math.min(lo[k], v.getComponent(k));
              hi[k] = Math.max(hi[k], v.getComponent(k));
            }
          }
        }
        return { name: mesh.name, count: mesh.count, visible: mesh.visible, min: lo, max: hi };
      });
      return {
        members,
        member_rows: document.querySelectorAll("#member-table tbody tr").length,
        density_svgs: document.querySelectorAll('#density figure[data-plot="debris_density"] svg').length,
      };
    })
  );
  // The rescue maps: per map, the cells drawn and the sum of their shares; the
  // distributions' medians; the places' rows.
  out.rescue = await page.evaluate(() => {
    const maps = {};
    for (const svg of document.querySelectorAll("#rescue svg.rescue-map")) {
      const ps = Array.from(svg.querySelectorAll("rect[data-p]")).map((r) => Number(r.dataset.p));
      maps[svg.dataset.column] = { cells: ps.length, sum: ps.reduce((a, b) => a + b, 0) };
    }
    const medians = {};
    for (const tr of document.querySelectorAll("#rescue-distributions tbody tr")) medians[tr.dataset.key] = Number(tr.dataset.median);
    return {
      maps,
      legend: !!document.getElementById("rescue-map-legend"),
      medians,
      places: Array.from(document.querySelectorAll("#rescue-places tbody tr")).map((tr) => Number(tr.dataset.probability)),
      none: document.getElementById("rescue-none") ? document.getElementById("rescue-none").textContent : null,
    };
  });
  await page.locator("#rescue").screenshot({ path: shot.replace(/\.png$/, "") + "_rescue.png" });
  // Unticking member 0 in the table hides its mesh.
  await page.locator('.member-toggle[data-member="0"]').uncheck();
  out.visible_after_untick = await page.evaluate(() => window.fem2rbdReport.meshes.map((m) => m.visible));
} finally {
  await browser.close();
}
process.stdout.write(JSON.stringify(out) + "\n");
