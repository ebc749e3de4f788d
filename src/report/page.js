// The report page's viewer: the run's bodies as one instanced box mesh, posed at any time
// of the timeline from the keyframes (positions interpolated linearly, rotations by slerp
// between the two frames around t), coloured by element type, story or connection state,
// with play/pause, a time slider, speed, orbit/zoom (OrbitControls), picking, and the
// cursor on the ground-motion strip. Data format: src/report/data.rs.
"use strict";
(function () {
  const data = JSON.parse(document.getElementById("report-data").textContent);

  function bytes(b64) {
    const bin = atob(b64);
    const out = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; i++) out[i] = bin.charCodeAt(i);
    return out.buffer;
  }
  function floats(b64) {
    return new Float32Array(bytes(b64));
  }
  // Box centres: origin + step · code, per axis (src/report/quantise.rs).
  function positions(p) {
    const codes = new Uint16Array(bytes(p.u16));
    const out = new Float32Array(codes.length);
    for (let i = 0; i < codes.length; i += 3) {
      for (let c = 0; c < 3; c++) out[i + c] = p.origin[c] + p.step * codes[i + c];
    }
    return out;
  }
  // Unit quaternions (x, y, z, w): code / scale, normalised.
  function rotations(r) {
    const codes = new Int16Array(bytes(r.i16));
    const out = new Float32Array(codes.length);
    for (let i = 0; i < codes.length; i += 4) {
      const x = codes[i], y = codes[i + 1], z = codes[i + 2], w = codes[i + 3];
      const n = Math.hypot(x, y, z, w) || 1;
      out[i] = x / n;
      out[i + 1] = y / n;
      out[i + 2] = z / n;
      out[i + 3] = w / n;
    }
    return out;
  }

  const times = data.times;
  const nFrames = times.length;
  const B = data.bodies;
  const nBodies = B.name.length;
  const pos = positions(data.position);
  const rot = rotations(data.rotation);
  const groundDisp = floats(data.ground.disp);
  const t0 = times[0];
  const t1 = times[nFrames - 1];

  // ---- scene ------------------------------------------------------------------------
  const canvas = document.getElementById("scene-canvas");
  const renderer = new THREE.WebGLRenderer({ canvas, antialias: true, preserveDrawingBuffer: true });
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  const scene = new THREE.Scene();
  scene.background = new THREE.Color(0xf4f6f8);
  const camera = new THREE.PerspectiveCamera(35, 1, 0.01, 5000);
  camera.up.set(0, 0, 1); // the run's z axis is up
  scene.add(new THREE.AmbientLight(0xffffff, 1.2));
  const sun = new THREE.DirectionalLight(0xffffff, 2.0);
  sun.position.set(0.5, -0.8, 1.0);
  scene.add(sun);

  const mesh = new THREE.InstancedMesh(
    new THREE.BoxGeometry(1, 1, 1),
    new THREE.MeshLambertMaterial({ color: 0xffffff }),
    nBodies
  );
  mesh.name = "bodies";
  scene.add(mesh);

  // The extent of the bodies over the first and last frames (centres ± half the largest
  // box size), for the ground and the camera.
  const lo = [Infinity, Infinity, Infinity];
  const hi = [-Infinity, -Infinity, -Infinity];
  for (const k of [0, nFrames - 1]) {
    for (let i = 0; i < nBodies; i++) {
      const r = 0.5 * Math.max(B.size[3 * i], B.size[3 * i + 1], B.size[3 * i + 2]);
      for (let c = 0; c < 3; c++) {
        const v = pos[(k * nBodies + i) * 3 + c];
        lo[c] = Math.min(lo[c], v - r);
        hi[c] = Math.max(hi[c], v + r);
      }
    }
  }
  const centre = new THREE.Vector3((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2);
  const radius = 0.5 * Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) || 1;

  const groundSize = 4 * Math.max(hi[0] - lo[0], hi[1] - lo[1], 1);
  const ground = new THREE.Mesh(
    new THREE.PlaneGeometry(groundSize, groundSize),
    new THREE.MeshLambertMaterial({ color: 0xcdd5c5 })
  );
  ground.name = "ground";
  scene.add(ground);
  const grid = new THREE.GridHelper(groundSize, Math.round(groundSize), 0x9aa59a, 0xb8c0b5);
  grid.rotation.x = Math.PI / 2; // GridHelper lies in x–z; the ground is x–y
  scene.add(grid);
  // The plane sits a hair below the base level so that the foundations' tops do not flicker.
  const groundDrop = 1e-3 * radius;

  const controls = new THREE.OrbitControls(camera, canvas);
  controls.target.copy(centre);
  controls.enableDamping = false;
  controls.addEventListener("change", () => render());

  function setView(kind) {
    const d = radius / Math.sin((camera.fov * Math.PI) / 360) * 1.05;
    if (kind === "plan") {
      camera.position.set(centre.x, centre.y - 1e-3 * d, centre.z + d);
    } else {
      const dir = new THREE.Vector3(0.55, -0.75, 0.45).normalize();
      camera.position.copy(centre).addScaledVector(dir, d);
    }
    controls.target.copy(centre);
    controls.update();
    state.view = kind;
    render();
  }

  // ---- colours -----------------------------------------------------------------------
  const palettes = data.palettes;
  const typeColour = {};
  for (const p of palettes.type) typeColour[p.name] = new THREE.Color(p.colour);
  const storyColours = palettes.story.map((p) => new THREE.Color(p.colour));
  const conn = palettes.connection;
  const connColours = conn ? conn.states.map((p) => new THREE.Color(p.colour)) : [];
  const connCount = new Int32Array(nBodies);
  if (conn) for (let c = 0; c < conn.a.length; c++) { connCount[conn.a[c]]++; connCount[conn.b[c]]++; }
  const pickColour = new THREE.Color(0xff00ff);

  // The connection state of each body at time t (legend order of data.rs).
  function connectionStates(t) {
    const out = new Int32Array(nBodies);
    if (data.ruin_start === null || t < data.ruin_start) return out.fill(5);
    const plastic = new Int32Array(nBodies);
    const broken = new Int32Array(nBodies);
    for (let c = 0; c < conn.a.length; c++) {
      const p = conn.plastic_from[c] !== null && conn.plastic_from[c] <= t;
      const b = conn.broken_from[c] !== null && conn.broken_from[c] <= t;
      for (const i of [conn.a[c], conn.b[c]]) {
        if (b) broken[i]++;
        else if (p) plastic[i]++;
      }
    }
    for (let i = 0; i < nBodies; i++) {
      if (connCount[i] === 0) out[i] = 0;
      else if (broken[i] === connCount[i]) out[i] = 4;
      else if (broken[i] > 0) out[i] = 3;
      else if (plastic[i] > 0) out[i] = 2;
      else out[i] = 1;
    }
    return out;
  }

  function legendEntries() {
    if (state.colour === "story") return palettes.story;
    if (state.colour === "connection") return conn.states;
    return palettes.type;
  }

  function applyColours() {
    const states = state.colour === "connection" ? connectionStates(state.t) : null;
    for (let i = 0; i < nBodies; i++) {
      let c;
      if (i === state.picked) c = pickColour;
      else if (state.colour === "story") c = storyColours[B.story[i]] || storyColours[0];
      else if (states) c = connColours[states[i]];
      else c = typeColour[B.type[i]];
      mesh.setColorAt(i, c);
    }
    mesh.instanceColor.needsUpdate = true;
  }

  function drawLegend() {
    const el = document.getElementById("legend");
    el.replaceChildren();
    for (const e of legendEntries()) {
      const row = document.createElement("div");
      const sw = document.createElement("span");
      sw.className = "swatch";
      sw.style.background = e.colour;
      row.append(sw, e.name);
      el.append(row);
    }
    state.legendVoids = voidsShown();
    if (state.legendVoids) {
      const head = document.createElement("div");
      head.textContent = "voids (faint: no adult fits)";
      head.style.marginTop = "4px";
      el.append(head);
      for (const e of V.patterns) {
        const row = document.createElement("div");
        const sw = document.createElement("span");
        sw.className = "swatch";
        sw.style.background = e.colour;
        row.append(sw, e.name);
        el.append(row);
      }
      const mk = document.createElement("div");
      mk.innerHTML = '<span class="swatch" style="background:#111"></span>rescuer\'s route and entry (post) <span class="swatch" style="background:#6e6e6e"></span>camera\'s route <span class="swatch" style="background:#d01010"></span>breach';
      el.append(mk);
    }
  }

  // ---- the voids of the final ruin (src/report/voids.rs) ----------------------------
  // One translucent instanced mesh per void: its cells as boxes of whole cells, one
  // instance each; markers where the rescuer's route enters a survivable void (a black
  // post standing on the entry point) or where debris must be breached to reach one (a
  // red cube on the first cell to cut). Shown at the final ruin only, with the bodies
  // made see-through so that the voids under the debris can be seen and picked.
  const V = data.voids;
  const voidMeshes = [];
  const markers = [];
  // Route lines (`route-N` the rescuer's, `camera-route-N` the camera's): the route of
  // voids.json from where it leaves open air to the void, simplified to within a cell;
  // each {name, points, segments}, a segment a mesh.
  const routeLines = [];
  const voidOpacity = (v) => (v.survivable ? V.opacity.survivable : V.opacity.other);
  if (V) {
    const h = V.cell;
    const o = V.origin;
    const unit = new THREE.BoxGeometry(1, 1, 1);
    const at = new THREE.Vector3();
    const size = new THREE.Vector3();
    const none = new THREE.Quaternion();
    const m4v = new THREE.Matrix4();
    for (const v of V.list) {
      const nb = v.boxes.length / 6;
      const m = new THREE.InstancedMesh(
        unit,
        new THREE.MeshLambertMaterial({
          color: v.colour, transparent: true, opacity: voidOpacity(v),
          depthWrite: false,
        }),
        nb
      );
      for (let b = 0; b < nb; b++) {
        const lo = [0, 1, 2].map((d) => o[d] + v.boxes[6 * b + d] * h);
        const hi = [0, 1, 2].map((d) => o[d] + v.boxes[6 * b + 3 + d] * h);
        at.set((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2);
        size.set(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
        m.setMatrixAt(b, m4v.compose(at, none, size));
      }
      m.instanceMatrix.needsUpdate = true;
      m.computeBoundingSphere();
      m.name = "void-" + v.void;
      m.userData.void = v.void;
      m.renderOrder = 2;
      scene.add(m);
      voidMeshes.push(m);
      const mark = (sx, sy, sz, p, colour, name) => {
        const mk = new THREE.Mesh(unit, new THREE.MeshLambertMaterial({ color: colour }));
        mk.scale.set(sx, sy, sz);
        mk.position.set(p[0], p[1], p[2]);
        mk.name = name;
        mk.renderOrder = 3;
        scene.add(mk);
        markers.push(mk);
      };
      if (v.entry) mark(h, h, 6 * h, [v.entry[0], v.entry[1], v.entry[2] + 3 * h], 0x111111, "entry-" + v.void);
      if (v.route) {
        // Each segment a thin opaque box along it (h/3 across): the inlined three.js
        // bundle draws meshes, and a box is seen at any zoom.
        const rescuer = v.route.who === "rescuer";
        const name = (rescuer ? "route-" : "camera-route-") + v.void;
        const mat = new THREE.MeshLambertMaterial({ color: rescuer ? 0x111111 : 0x6e6e6e });
        const p = v.route.points;
        const segments = [];
        const a = new THREE.Vector3();
        const b = new THREE.Vector3();
        const d = new THREE.Vector3();
        const xAxis = new THREE.Vector3(1, 0, 0);
        for (let k = 0; k + 5 < p.length; k += 3) {
          a.set(p[k], p[k + 1], p[k + 2]);
          b.set(p[k + 3], p[k + 4], p[k + 5]);
          d.subVectors(b, a);
          const len = d.length();
          if (len === 0) continue;
          const seg = new THREE.Mesh(unit, mat);
          seg.scale.set(len, h / 3, h / 3);
          seg.quaternion.setFromUnitVectors(xAxis, d.normalize());
          seg.position.set((a.x + b.x) / 2, (a.y + b.y) / 2, (a.z + b.z) / 2);
          seg.name = name;
          seg.renderOrder = 4;
          scene.add(seg);
          segments.push(seg);
        }
        routeLines.push({ name, points: p, segments });
      }
      if (v.breach) mark(2 * h, 2 * h, 2 * h, v.breach, 0xd01010, "breach-" + v.void);
    }
  }
  const showVoidsBox = document.getElementById("show-voids");

  // Whether the voids are drawn now: there are some, they are switched on, and the time
  // is the final ruin's.
  function voidsShown() {
    return !!V && !!showVoidsBox && showVoidsBox.checked && state.t >= t1;
  }

  function applyVoids() {
    const on = voidsShown();
    for (const m of voidMeshes) m.visible = on;
    for (const m of markers) m.visible = on;
    for (const l of routeLines) for (const seg of l.segments) seg.visible = on;
    mesh.material.transparent = on;
    mesh.material.opacity = on ? 0.3 : 1;
    mesh.material.depthWrite = !on;
    mesh.material.needsUpdate = true;
    for (const m of voidMeshes) {
      const picked = m.userData.void === state.pickedVoid;
      m.material.opacity = picked ? 0.85 : voidOpacity(V.list[m.userData.void - 1]);
      m.material.emissive.setHex(picked ? 0x505050 : 0x000000);
    }
  }

  // ---- time --------------------------------------------------------------------------
  const m4 = new THREE.Matrix4();
  const p3 = new THREE.Vector3();
  const q4 = new THREE.Quaternion();
  const s3 = new THREE.Vector3();
  const qa = new Float32Array(4);

  // The frame k and weight f with t between times[k] and times[k + 1].
  function frameAt(t) {
    if (t <= t0 || nFrames === 1) return [0, 0];
    if (t >= t1) return [nFrames - 1, 0];
    let a = 0;
    let b = nFrames - 1;
    while (b - a > 1) {
      const m = (a + b) >> 1;
      if (times[m] <= t) a = m;
      else b = m;
    }
    return [a, (t - times[a]) / (times[b] - times[a])];
  }

  function poseBodies(t) {
    const [k, f] = frameAt(t);
    const k1 = Math.min(k + 1, nFrames - 1);
    for (let i = 0; i < nBodies; i++) {
      const a = (k * nBodies + i) * 3;
      const b = (k1 * nBodies + i) * 3;
      p3.set(
        pos[a] + f * (pos[b] - pos[a]),
        pos[a + 1] + f * (pos[b + 1] - pos[a + 1]),
        pos[a + 2] + f * (pos[b + 2] - pos[a + 2])
      );
      THREE.Quaternion.slerpFlat(qa, 0, rot, (k * nBodies + i) * 4, rot, (k1 * nBodies + i) * 4, f);
      q4.set(qa[0], qa[1], qa[2], qa[3]);
      s3.set(B.size[3 * i], B.size[3 * i + 1], B.size[3 * i + 2]);
      mesh.setMatrixAt(i, m4.compose(p3, q4, s3));
    }
    mesh.instanceMatrix.needsUpdate = true;
    mesh.computeBoundingSphere();
    const g = (c) => groundDisp[3 * k + c] + f * (groundDisp[3 * k1 + c] - groundDisp[3 * k + c]);
    ground.position.set(centre.x + g(0), centre.y + g(1), data.ground.top + g(2) - groundDrop);
    grid.position.set(centre.x + g(0), centre.y + g(1), data.ground.top + g(2) - groundDrop / 2);
  }

  const slider = document.getElementById("time-slider");
  const readout = document.getElementById("time-readout");
  const cursor = document.getElementById("strip-cursor");
  const state = { t: t0, playing: false, speed: 1, colour: "type", view: "3d", picked: -1, pickedVoid: -1 };

  function stageAt(t) {
    if (data.ruin_start !== null && t >= data.ruin_start) return "ruin stage";
    return "FE stage";
  }

  function setTime(t) {
    state.t = Math.min(Math.max(t, t0), t1);
    slider.value = String(state.t);
    const u = t1 > t0 ? (1000 * (state.t - t0)) / (t1 - t0) : 0;
    cursor.setAttribute("x1", u.toFixed(2));
    cursor.setAttribute("x2", u.toFixed(2));
    readout.textContent =
      "t = " + state.t.toFixed(3) + " s · " + stageAt(state.t) +
      (data.tc !== null ? " · Tc = " + data.tc + " s" : "");
    poseBodies(state.t);
    applyColours();
    applyVoids();
    if (voidsShown() !== state.legendVoids) drawLegend();
    render();
  }

  // ---- rendering and resizing ----------------------------------------------------------
  function resize() {
    const w = canvas.clientWidth;
    const h = canvas.clientHeight;
    if (canvas.width !== Math.round(w * renderer.getPixelRatio()) || canvas.height !== Math.round(h * renderer.getPixelRatio())) {
      renderer.setSize(w, h, false);
      camera.aspect = w / Math.max(h, 1);
      camera.updateProjectionMatrix();
    }
  }
  function render() {
    resize();
    renderer.render(scene, camera);
  }
  window.addEventListener("resize", render);

  // ---- playing -------------------------------------------------------------------------
  const playButton = document.getElementById("play");
  let last = null;
  function setPlaying(on) {
    state.playing = on;
    playButton.textContent = on ? "❚❚ pause" : "▶ play";
    last = null;
    if (on) {
      if (state.t >= t1) setTime(t0);
      requestAnimationFrame(tick);
    }
  }
  function tick(now) {
    if (!state.playing) return;
    if (last !== null) {
      const t = state.t + ((now - last) / 1000) * state.speed;
      setTime(t);
      if (t >= t1) {
        setPlaying(false);
        return;
      }
    }
    last = now;
    requestAnimationFrame(tick);
  }
  playButton.addEventListener("click", () => setPlaying(!state.playing));
  slider.addEventListener("input", () => {
    setPlaying(false);
    setTime(Number(slider.value));
  });
  document.getElementById("speed").addEventListener("change", (e) => {
    state.speed = Number(e.target.value);
  });
  const colourBy = document.getElementById("colour-by");
  function setColour(kind) {
    if (kind === "connection" && !conn) kind = "type";
    state.colour = kind;
    colourBy.value = kind;
    drawLegend();
    applyColours();
    render();
  }
  colourBy.addEventListener("change", () => setColour(colourBy.value));
  document.getElementById("view-3d").addEventListener("click", () => setView("3d"));
  document.getElementById("view-plan").addEventListener("click", () => setView("plan"));
  const gotoTc = document.getElementById("goto-tc");
  if (gotoTc) gotoTc.addEventListener("click", () => { setPlaying(false); setTime(data.tc); });
  document.getElementById("goto-end").addEventListener("click", () => { setPlaying(false); setTime(t1); });

  // ---- picking -------------------------------------------------------------------------
  const raycaster = new THREE.Raycaster();
  const info = document.getElementById("pick-info");

  function select(i) {
    const prev = document.querySelector("#body-table tr.picked");
    if (prev) prev.classList.remove("picked");
    state.picked = i;
    if (i < 0) {
      info.hidden = true;
    } else {
      const row = document.getElementById("body-" + i);
      row.classList.add("picked");
      row.scrollIntoView({ block: "nearest" });
      const cells = Array.from(row.cells).map((c) => c.textContent);
      const heads = Array.from(document.querySelectorAll("#body-table thead th")).map((c) => c.textContent);
      const table = document.createElement("table");
      heads.forEach((h, k) => {
        const tr = table.insertRow();
        const th = document.createElement("th");
        th.textContent = h;
        tr.append(th);
        tr.insertCell().textContent = cells[k];
      });
      info.replaceChildren(table);
      info.dataset.body = String(i);
      info.hidden = false;
    }
    applyColours();
    render();
  }

  // The body drawn at client point (x, y), or -1.
  function pickAt(x, y) {
    const r = canvas.getBoundingClientRect();
    const ndc = new THREE.Vector2(((x - r.left) / r.width) * 2 - 1, -((y - r.top) / r.height) * 2 + 1);
    raycaster.setFromCamera(ndc, camera);
    const hit = raycaster.intersectObject(mesh, false)[0];
    return hit ? hit.instanceId : -1;
  }

  // The void drawn at client point (x, y) (the nearest along the ray), or -1 when none is
  // drawn there or the voids are not shown.
  function pickVoidAt(x, y) {
    if (!voidsShown()) return -1;
    const r = canvas.getBoundingClientRect();
    const ndc = new THREE.Vector2(((x - r.left) / r.width) * 2 - 1, -((y - r.top) / r.height) * 2 + 1);
    raycaster.setFromCamera(ndc, camera);
    const hit = raycaster.intersectObjects(voidMeshes, false)[0];
    return hit ? hit.object.userData.void : -1;
  }

  // Picks void n (its number in voids.csv; -1: none): highlights its mesh and its row of
  // the voids table, and goes to the final ruin with the voids shown.
  function selectVoid(n) {
    const prev = document.querySelector("#void-table tr.picked");
    if (prev) prev.classList.remove("picked");
    state.pickedVoid = n;
    if (n > 0) {
      const row = document.getElementById("void-" + n);
      row.classList.add("picked");
      row.scrollIntoView({ block: "nearest" });
      if (showVoidsBox) showVoidsBox.checked = true;
      if (state.t < t1) {
        setPlaying(false);
        setTime(t1);
        return;
      }
    }
    applyVoids();
    drawLegend();
    render();
  }

  let down = null;
  canvas.addEventListener("pointerdown", (e) => { down = [e.clientX, e.clientY]; });
  canvas.addEventListener("pointerup", (e) => {
    if (down && Math.hypot(e.clientX - down[0], e.clientY - down[1]) < 4) {
      const v = pickVoidAt(e.clientX, e.clientY);
      if (v > 0) selectVoid(v);
      else select(pickAt(e.clientX, e.clientY));
    }
    down = null;
  });
  document.querySelector("#body-table tbody").addEventListener("click", (e) => {
    const tr = e.target.closest("tr");
    if (tr) select(Number(tr.dataset.body));
  });

  const voidTable = document.querySelector("#void-table tbody");
  if (voidTable) {
    voidTable.addEventListener("click", (e) => {
      const tr = e.target.closest("tr");
      if (tr) selectVoid(Number(tr.dataset.void));
    });
  }
  if (showVoidsBox) {
    showVoidsBox.addEventListener("change", () => {
      applyVoids();
      drawLegend();
      render();
    });
  }
  function showVoids(on) {
    if (!showVoidsBox) return;
    showVoidsBox.checked = on;
    applyVoids();
    drawLegend();
    render();
  }

  // ---- start: #t=SECONDS&colour=KIND&view=plan -----------------------------------------
  const params = new URLSearchParams(location.hash.slice(1));
  setColour(params.get("colour") || "type");
  setView(params.get("view") === "plan" ? "plan" : "3d");
  const tStart = Number(params.get("t"));
  setTime(params.has("t") && Number.isFinite(tStart) ? tStart : t0);

  // For scripts driving the page (the browser test, a user's console).
  window.fem2rbdReport = {
    times, bodies: nBodies, mesh, camera, scene, renderer, state,
    setTime, setColour, setView, select, pickAt, render,
    voidMeshes, markers, routeLines, selectVoid, pickVoidAt, showVoids, voidsShown,
  };
  document.documentElement.dataset.reportReady = "1";
})();
