// Opens a study report page (`fem2rbd report STUDY_DIR`) in Debian's headless Chromium
// through playwright-core, reads what it shows and takes a screenshot of the whole page.
// Prints one JSON object on stdout for tests/it/report/study.rs.
//
//   node tests/report/check_study.mjs REPORT.html SCREENSHOT.png
import { chromium } from "playwright-core";
import path from "node:path";
import { pathToFileURL } from "node:url";

const [report, shot] = process.argv.slice(2);
if (!report || !shot) {
  console.error("usage: node check_study.mjs REPORT.html SCREENSHOT.png");
  process.exit(2);
}
const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
  headless: true,
  args: ["--no-sandbox"],
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
  await page.goto(pathToFileURL(path.resolve(report)).href, { waitUntil: "load" });
  await page.screenshot({ path: shot, fullPage: true });
  Object.assign(
    out,
    await page.evaluate(() => {
      const svgBox = (f) => {
        const s = f.querySelector("svg");
        if (!s) return null;
        const r = s.getBoundingClientRect();
        return { width: r.width, height: r.height };
      };
      return {
        title: document.title,
        fragility: Array.from(document.querySelectorAll("#fragility-table tbody tr")).map((tr) => ({
          model: tr.dataset.model,
          mode: tr.dataset.mode,
          median: tr.dataset.median,
        })),
        figures: Array.from(document.querySelectorAll("#study-figures figure")).map((f) => ({
          plot: f.dataset.plot,
          svg: svgBox(f),
        })),
        intensities: Array.from(document.querySelectorAll("section.intensity")).map((s) => ({
          stem: s.dataset.stem,
          density: Array.from(s.querySelectorAll("figure[data-plot^='density_']")).map((f) => ({
            plot: f.dataset.plot,
            svg: svgBox(f),
          })),
          maps: Array.from(s.querySelectorAll(".rescue-maps figure")).map((f) => ({
            map: f.dataset.map,
            cells: f.querySelectorAll("rect[data-p]").length,
            shares: Array.from(f.querySelectorAll("rect[data-p]")).map((r) => Number(r.dataset.p)),
          })),
          medians: Object.fromEntries(
            Array.from(s.querySelectorAll(".rescue-distributions tbody tr")).map((tr) => [tr.dataset.key, Number(tr.dataset.median)])
          ),
          places: Array.from(s.querySelectorAll(".rescue-places tbody tr")).map((tr) => Number(tr.dataset.probability)),
        })),
        ids: Array.from(document.querySelectorAll("[id]")).map((e) => e.id),
      };
    })
  );
} finally {
  await browser.close();
}
console.log(JSON.stringify(out));
