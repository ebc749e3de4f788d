// The ensemble report's viewer: each member's final ruin as one instanced box mesh in the
// member's colour, overlaid; members shown or hidden from the member table; orbit/zoom
// (OrbitControls). Data format: src/report/ensemble.rs.
"use strict";
(function () {
  const data = JSON.parse(document.getElementById("report-data").textContent);

  function floats(b64) {
    const bin = atob(b64);
    const bytes = new Uint8Array(bin.length);
    for (let i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
    return new Float32Array(bytes.buffer);
  }

  const B = data.bodies;
  const nBodies = B.name.length;
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

  const lo = [Infinity, Infinity, Infinity];
  const hi = [-Infinity, -Infinity, -Infinity];
  const box = new THREE.BoxGeometry(1, 1, 1);
  const m4 = new THREE.Matrix4();
  const p3 = new THREE.Vector3();
  const q4 = new THREE.Quaternion();
  const s3 = new THREE.Vector3();
  const meshes = data.members.map((member) => {
    const pos = floats(member.position);
    const rot = floats(member.rotation);
    const mesh = new THREE.InstancedMesh(
      box,
      new THREE.MeshLambertMaterial({ color: member.colour, transparent: true, opacity: 0.55 }),
      nBodies
    );
    mesh.name = member.name;
    for (let i = 0; i < nBodies; i++) {
      p3.set(pos[3 * i], pos[3 * i + 1], pos[3 * i + 2]);
      q4.set(rot[4 * i], rot[4 * i + 1], rot[4 * i + 2], rot[4 * i + 3]);
      s3.set(B.size[3 * i], B.size[3 * i + 1], B.size[3 * i + 2]);
      mesh.setMatrixAt(i, m4.compose(p3, q4, s3));
      const r = 0.5 * Math.max(s3.x, s3.y, s3.z);
      for (let c = 0; c < 3; c++) {
        lo[c] = Math.min(lo[c], p3.getComponent(c) - r);
        hi[c] = Math.max(hi[c], p3.getComponent(c) + r);
      }
    }
    mesh.instanceMatrix.needsUpdate = true;
    mesh.computeBoundingSphere();
    scene.add(mesh);
    return mesh;
  });

  const centre = new THREE.Vector3((lo[0] + hi[0]) / 2, (lo[1] + hi[1]) / 2, (lo[2] + hi[2]) / 2);
  const radius = 0.5 * Math.hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]) || 1;
  const groundSize = 4 * Math.max(hi[0] - lo[0], hi[1] - lo[1], 1);
  const grid = new THREE.GridHelper(groundSize, Math.round(groundSize), 0x9aa59a, 0xb8c0b5);
  grid.rotation.x = Math.PI / 2; // GridHelper lies in x–z; the ground is x–y
  grid.position.set(centre.x, centre.y, lo[2]);
  scene.add(grid);

  const controls = new THREE.OrbitControls(camera, canvas);
  controls.addEventListener("change", () => render());

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

  function setView(kind) {
    const d = (radius / Math.sin((camera.fov * Math.PI) / 360)) * 1.05;
    if (kind === "plan") {
      camera.position.set(centre.x, centre.y - 1e-3 * d, centre.z + d);
    } else {
      const dir = new THREE.Vector3(0.55, -0.75, 0.45).normalize();
      camera.position.copy(centre).addScaledVector(dir, d);
    }
    controls.target.copy(centre);
    controls.update();
    render();
  }

  function show(m, on) {
    meshes[m].visible = on;
    document.querySelector('.member-toggle[data-member="' + m + '"]').checked = on;
    render();
  }
  for (const box of document.querySelectorAll(".member-toggle")) {
    box.addEventListener("change", () => show(Number(box.dataset.member), box.checked));
  }
  document.getElementById("show-all").addEventListener("click", () => meshes.forEach((_, m) => show(m, true)));
  document.getElementById("view-3d").addEventListener("click", () => setView("3d"));
  document.getElementById("view-plan").addEventListener("click", () => setView("plan"));

  setView(new URLSearchParams(location.hash.slice(1)).get("view") === "plan" ? "plan" : "3d");

  // For scripts driving the page (the browser test, a user's console).
  window.fem2rbdReport = { bodies: nBodies, meshes, camera, scene, renderer, show, setView, render };
  document.documentElement.dataset.reportReady = "1";
})();
