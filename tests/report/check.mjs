// Opens a report page (`fem2rbd report`) in Debian's headless Chromium through
// playwright-core (pinned in tests/report/package.json), reads what the page shows and
// takes screenshots of its 3-D view at given times. Prints one JSON object on stdout; the
// Rust test (tests/it/report/browser.rs) asserts it against the run folder's own numbers.
//
//   node tests/report/check.mjs REPORT.html OUT_DIR NAME=T [NAME=T ...]
//
// Writes OUT_DIR/NAME.png for each NAME=T (T in s). Chromium: $CHROMIUM, else
// /usr/bin/chromium (`apt-get install chromium`); WebGL through SwiftShader (software).
import { chromium } from "playwright-core";
import path from "node:path";
import { pathToFileURL } from "node:url";

const [report, outDir, ...shots] = process.argv.slice(2);
if (!report || !outDir) {
  console.error("usage: node check.mjs REPORT.html OUT_DIR NAME=T ...");
  process.exit(2);
}

const browser = await chromium.launch({
  executablePath: process.env.CHROMIUM || "/usr/bin/chromium",
  headless: true,
  args: ["--use-angle=swiftshader", "--enable-unsafe-swiftshader", "--ignore-gpu-blocklist", "--no-sandbox"],
});
const out = { errors: [], shots: [] };
try {
  const page = await browser.newPage({ viewport: { width: 1280, height: 900 }, deviceScaleFactor: 1 });
  page.on("pageerror", (e) => out.errors.push("pageerror: " + e.message));
  page.on("console", (m) => {
    if (m.type() === "error") out.errors.push("console.error: " + m.text());
  });
  page.on("requestfailed", (r) => out.errors.push("request failed: " + r.url()));
  // Offline: any request leaving the file itself is an error.
  await page.route(/^(?!file:).*/, (route) => {
    out.errors.push("network request: " + route.request().url());
    return route.abort();
  });
  await page.goto(pathToFileURL(path.resolve(report)).href);
  await page.waitForFunction(() => document.documentElement.dataset.reportReady === "1", null, {
    timeout: 60000,
  });

  Object.assign(
    out,
    await page.evaluate(() => {
      const r = window.fem2rbdReport;
      const slider = document.getElementById("time-slider");
      const tcCell = document.querySelector('#key-figures tr[data-key="tc_s"] td');
      return {
        bodies_in_scene: r.mesh.count,
        scene_children: r.scene.children.map((c) => c.name || c.type),
        body_rows: document.querySelectorAll("#body-table tbody tr").length,
        slider_min: Number(slider.min),
        slider_max: Number(slider.max),
        times: r.times,
        key_figure_tc: tcCell ? tcCell.dataset.value ?? null : null,
        key_figure_tc_text: tcCell ? tcCell.textContent : null,
        plots: document.querySelectorAll("#plots figure svg").length,
        colour_options: Array.from(document.querySelectorAll("#colour-by option")).map((o) => o.value),
      };
    })
  );

  for (const s of shots) {
    const [name, t] = s.split("=");
    const readout = await page.evaluate((t) => {
      window.fem2rbdReport.setTime(t);
      return document.getElementById("time-readout").textContent;
    }, Number(t));
    const file = path.join(outDir, name + ".png");
    await page.locator("#view").screenshot({ path: file });
    out.shots.push({ name, t: Number(t), file, readout });
  }

  // The checks of the bodies below see them opaque: the voids off.
  await page.evaluate(() => window.fem2rbdReport.showVoids(false));

  // At the end of the timeline: the world box of the drawn active bodies (the corners of
  // each instance's unit box through its matrix) and, in the 3-D view, the drawn bodies'
  // box on the canvas in pixels.
  Object.assign(
    out,
    await page.evaluate(() => {
      const r = window.fem2rbdReport;
      const T = window.THREE;
      r.setView("3d");
      r.setTime(r.times[r.times.length - 1]);
      const passive = JSON.parse(document.getElementById("report-data").textContent).bodies.passive;
      const m = new T.Matrix4();
      const v = new T.Vector3();
      const lo = [Infinity, Infinity, Infinity];
      const hi = [-Infinity, -Infinity, -Infinity];
      const px = [Infinity, Infinity, -Infinity, -Infinity];
      const canvas = r.renderer.domElement;
      const w = canvas.clientWidth;
      const h = canvas.clientHeight;
      for (let i = 0; i < r.mesh.count; i++) {
        r.mesh.getMatrixAt(i, m);
        for (let c = 0; c < 8; c++) {
          v.set(c & 1 ? 0.5 : -0.5, c & 2 ? 0.5 : -0.5, c & 4 ? 0.5 : -0.5).applyMatrix4(m);
          if (!passive[i]) {
            for (let k = 0; k < 3; k++) {
              lo[k] = Math.min(lo[k], v.getComponent(k));
              hi[k] = Math.max(hi[k], v.getComponent(k));
            }
          }
          v.project(r.camera);
          const x = ((v.x + 1) / 2) * w;
          const y = ((1 - v.y) / 2) * h;
          px[0] = Math.min(px[0], x);
          px[1] = Math.min(px[1], y);
          px[2] = Math.max(px[2], x);
          px[3] = Math.max(px[3], y);
        }
      }
      return { rest_world_min: lo, rest_world_max: hi, rest_pixels: px, canvas: [w, h] };
    })
  );

  // Plan view at rest: a screenshot of the canvas alone, the drawn active bodies' box on
  // it in pixels (corners through the camera), and the legend's box on it (to be left
  // out of the picture's analysis).
  const planShot = path.join(outDir, "plan_at_rest.png");
  Object.assign(
    out,
    await page.evaluate(() => {
      const r = window.fem2rbdReport;
      const T = window.THREE;
      r.setView("plan");
      r.setTime(r.times[r.times.length - 1]);
      const passive = JSON.parse(document.getElementById("report-data").textContent).bodies.passive;
      const m = new T.Matrix4();
      const v = new T.Vector3();
      const canvas = r.renderer.domElement;
      const w = canvas.clientWidth;
      const h = canvas.clientHeight;
      const px = [Infinity, Infinity, -Infinity, -Infinity];
      for (let i = 0; i < r.mesh.count; i++) {
        if (passive[i]) continue;
        r.mesh.getMatrixAt(i, m);
        for (let c = 0; c < 8; c++) {
          v.set(c & 1 ? 0.5 : -0.5, c & 2 ? 0.5 : -0.5, c & 4 ? 0.5 : -0.5).applyMatrix4(m).project(r.camera);
          const x = ((v.x + 1) / 2) * w;
          const y = ((1 - v.y) / 2) * h;
          px[0] = Math.min(px[0], x);
          px[1] = Math.min(px[1], y);
          px[2] = Math.max(px[2], x);
          px[3] = Math.max(px[3], y);
        }
      }
      const c = canvas.getBoundingClientRect();
      const l = document.getElementById("legend").getBoundingClientRect();
      return {
        plan_pixels: px,
        plan_legend: [l.left - c.left, l.top - c.top, l.right - c.left, l.bottom - c.top],
      };
    })
  );
  await page.locator("#scene-canvas").screenshot({ path: planShot });
  out.plan_shot = planShot;

  // Picking in plan view at rest: click the projected centre of the top face of the body
  // whose top face is highest; the page must show that body's row.
  const target = await page.evaluate(() => {
    const r = window.fem2rbdReport;
    const T = window.THREE;
    r.setView("plan");
    const m = new T.Matrix4();
    const v = new T.Vector3();
    let best = -1;
    let bestZ = -Infinity;
    for (let i = 0; i < r.mesh.count; i++) {
      r.mesh.getMatrixAt(i, m);
      let z = -Infinity;
      for (let c = 0; c < 8; c++) {
        v.set(c & 1 ? 0.5 : -0.5, c & 2 ? 0.5 : -0.5, c & 4 ? 0.5 : -0.5).applyMatrix4(m);
        z = Math.max(z, v.z);
      }
      if (z > bestZ) {
        bestZ = z;
        best = i;
      }
    }
    r.mesh.getMatrixAt(best, m);
    v.setFromMatrixPosition(m).project(r.camera);
    const rect = r.renderer.domElement.getBoundingClientRect();
    return {
      body: best,
      x: rect.left + ((v.x + 1) / 2) * rect.width,
      y: rect.top + ((1 - v.y) / 2) * rect.height,
    };
  });
  await page.mouse.click(target.x, target.y);
  out.pick = await page.evaluate((target) => {
    const info = document.getElementById("pick-info");
    const row = document.querySelector("#body-table tr.picked");
    return {
      wanted: target.body,
      shown: info.hidden ? null : Number(info.dataset.body),
      row_name: row ? row.cells[1].textContent : null,
      info_text: info.textContent,
    };
  }, target);

  // The voids at the final ruin: the meshes (name, boxes, the volume of the drawn boxes:
  // each instance is the unit cube through its matrix, so its volume is the matrix's
  // determinant), the markers, the table rows and the rescue key figures.
  out.voids = await page.evaluate(() => {
    const r = window.fem2rbdReport;
    r.select(-1);
    r.showVoids(true);
    r.setView("3d");
    r.setTime(r.times[r.times.length - 1]);
    const m4 = new window.THREE.Matrix4();
    const meshes = r.voidMeshes.map((m) => {
      let vol = 0;
      for (let i = 0; i < m.count; i++) {
        m.getMatrixAt(i, m4);
        vol += Math.abs(m4.determinant());
      }
      return { name: m.name, boxes: m.count, volume: vol, visible: m.visible };
    });
    const cell = (key) => {
      const td = document.querySelector(`#key-figures tr[data-key="${key}"] td`);
      return td ? Number(td.dataset.value) : null;
    };
    const none = document.getElementById("voids-none");
    return {
      shown: r.voidsShown(),
      meshes,
      in_scene: r.scene.children.filter((c) => /^void-[0-9]+$/.test(c.name)).length,
      markers: r.markers.map((m) => m.name),
      // Each route's drawn points: its segments' ends, each the unit box's ±x face centre
      // through the segment's world matrix.
      routes: r.routeLines.map((l) => {
        const pts = [];
        const v = new window.THREE.Vector3();
        l.segments.forEach((s, k) => {
          s.updateMatrixWorld();
          if (k === 0) {
            v.set(-0.5, 0, 0).applyMatrix4(s.matrixWorld);
            pts.push(v.x, v.y, v.z);
          }
          v.set(0.5, 0, 0).applyMatrix4(s.matrixWorld);
          pts.push(v.x, v.y, v.z);
        });
        return { name: l.name, visible: l.segments.length > 0 && l.segments.every((s) => s.visible), points: pts };
      }),
      rows: Array.from(document.querySelectorAll("#void-table tbody tr")).map((tr) => Number(tr.dataset.void)),
      none: none ? none.textContent : null,
      key_voids_count: cell("rescue.voids_count"),
      key_survivable_count: cell("rescue.survivable_count"),
      key_survivable_volume: cell("rescue.survivable_volume_m3"),
      key_pile_height: cell("rescue.pile_max_height_m"),
    };
  });

  if (out.voids.meshes.length > 0) {
    // A row picks its void: the mesh is highlighted.
    out.void_row_pick = await page.evaluate(() => {
      const r = window.fem2rbdReport;
      const n = r.voidMeshes.length;
      document.getElementById("void-" + n).click();
      const m = r.voidMeshes[n - 1];
      return { wanted: n, picked: r.state.pickedVoid, opacity: m.material.opacity, row: document.querySelector("#void-table tr.picked").dataset.void };
    });
    // A click in the view picks the nearest void along the ray through the centre of the
    // largest void's first box; its row is highlighted.
    const target = await page.evaluate(() => {
      const r = window.fem2rbdReport;
      const T = window.THREE;
      r.renderer.domElement.scrollIntoView();
      const d = JSON.parse(document.getElementById("report-data").textContent).voids;
      const b = d.list[0].boxes;
      const c = new T.Vector3(...[0, 1, 2].map((k) => d.origin[k] + 0.5 * (b[k] + b[k + 3]) * d.cell));
      const ndc = c.clone().project(r.camera);
      const ray = new T.Raycaster();
      ray.setFromCamera(new T.Vector2(ndc.x, ndc.y), r.camera);
      const hit = ray.intersectObjects(r.voidMeshes, false)[0];
      const rect = r.renderer.domElement.getBoundingClientRect();
      return {
        wanted: hit ? hit.object.userData.void : -1,
        x: rect.left + ((ndc.x + 1) / 2) * rect.width,
        y: rect.top + ((1 - ndc.y) / 2) * rect.height,
      };
    });
    await page.mouse.click(target.x, target.y);
    out.void_view_pick = await page.evaluate((target) => {
      const row = document.querySelector("#void-table tr.picked");
      return { wanted: target.wanted, picked: window.fem2rbdReport.state.pickedVoid, row: row ? Number(row.dataset.void) : null };
    }, target);
    const voidShot = path.join(outDir, "voids_at_rest.png");
    await page.locator("#view").screenshot({ path: voidShot });
    out.void_shot = voidShot;
  }
} finally {
  await browser.close();
}
process.stdout.write(JSON.stringify(out) + "\n");
