// The dashboard's live 3D view: the HTML replay's renderer (client/assets/replay.html:
// the same three.js r170, shapes, palette, lights, ground grid and camera), fed with
// scenes the page polls from the server instead of recorded frames.
import * as THREE from './three.js';
import { OrbitControls } from './OrbitControls.js';

const PALETTE = [0x8c949e, 0xf29926, 0x3380d9, 0xe6cc40, 0x73bf8c, 0xb373cc];

// A body's geometry from its shape, as the replay builds it (cylinders and capsules
// along y, as in gymfleet).
function geometryOf(shape) {
  if (shape.box) {
    const [x, y, z] = shape.box;
    return new THREE.BoxGeometry(2 * x, 2 * y, 2 * z);
  }
  if (shape.cylinder) {
    const [r, h] = shape.cylinder;
    return new THREE.CylinderGeometry(r, r, 2 * h, 32);
  }
  if (shape.capsule) {
    const [r, h] = shape.capsule;
    return new THREE.CapsuleGeometry(r, 2 * h, 8, 24);
  }
  if (shape.mesh) {
    const [vertices, triangles] = shape.mesh;
    const geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.Float32BufferAttribute(vertices, 3));
    geometry.setIndex(triangles);
    geometry.computeVertexNormals();
    return geometry;
  }
  return new THREE.SphereGeometry(shape.sphere, 24, 12);
}

export class SceneView {
  // Throws if the browser has no WebGL.
  constructor(container) {
    this.container = container;
    this.renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    this.renderer.setPixelRatio(1);
    container.appendChild(this.renderer.domElement);
    this.camera = new THREE.PerspectiveCamera(45, 1, 0.1, 1000);
    this.camera.up.set(0, 0, 1);
    this.controls = new OrbitControls(this.camera, this.renderer.domElement);
    this.controls.addEventListener('change', () => this.draw());
    this.key = null;
    this.scene = null;
    // Resizing in the next frame, not in the observer's callback, so that a resize can
    // never feed back into the observer within one frame.
    new ResizeObserver(() => requestAnimationFrame(() => { this.resize(); this.draw(); })).observe(container);
    this.resize();
  }

  get canvas() { return this.renderer.domElement; }

  // Builds the world for a scene's bodies and frames the camera on its first poses.
  build(data) {
    if (this.scene) this.dispose();
    const scene = new THREE.Scene();
    scene.background = new THREE.Color(0xe9edf2);
    scene.add(new THREE.AmbientLight(0xffffff, 0.55));
    const sun = new THREE.DirectionalLight(0xffffff, 1.6);
    sun.position.set(1, -1.5, 2);
    scene.add(sun);
    this.bodies = data.bodies.map((body) => {
      const material = new THREE.MeshLambertMaterial({ color: PALETTE[body.instance % PALETTE.length] });
      const mesh = new THREE.Mesh(geometryOf(body.shape), material);
      mesh.name = body.name;
      scene.add(mesh);
      return mesh;
    });
    const marker = (colour, radius) => {
      const m = new THREE.Mesh(new THREE.SphereGeometry(radius, 16, 8),
        new THREE.MeshBasicMaterial({ color: colour, depthTest: false }));
      m.renderOrder = 1;
      scene.add(m);
      return m;
    };

    // Size of things: the bounding sphere of the first poses, padded by the largest body.
    const box = new THREE.Box3();
    for (const p of data.poses) box.expandByPoint(new THREE.Vector3(p[0], p[1], p[2]));
    for (const b of this.bodies) b.geometry.computeBoundingSphere();
    const pad = Math.max(...this.bodies.map((b) => b.geometry.boundingSphere.radius), 1);
    box.expandByScalar(pad);
    box.min.z = Math.min(box.min.z, 0);
    const centre = box.getCenter(new THREE.Vector3());
    const radius = Math.max(box.getSize(new THREE.Vector3()).length() / 2, 1);
    this.ees = (data.end_effectors ?? []).map(() => marker(0x0da626, radius * 0.02));
    this.target = marker(0xd91acc, radius * 0.03);

    // Ground grid on z = 0, spacing 1/2/5 x 10^n mm.
    const raw = radius / 5;
    const decade = Math.pow(10, Math.floor(Math.log10(raw)));
    this.spacing = [1, 2, 5, 10].map((m) => m * decade).find((s) => s >= raw);
    const divisions = 2 * Math.ceil(radius * 1.5 / this.spacing);
    const grid = new THREE.GridHelper(divisions * this.spacing, divisions, 0x5c6370, 0xa3a8b0);
    grid.rotation.x = Math.PI / 2;
    grid.position.set(Math.round(centre.x / this.spacing) * this.spacing,
      Math.round(centre.y / this.spacing) * this.spacing, 0);
    scene.add(grid);

    this.camera.near = radius / 100;
    this.camera.far = radius * 100;
    this.camera.position.copy(centre)
      .add(new THREE.Vector3(1, -1, 0.8).normalize().multiplyScalar(radius / Math.sin(Math.PI / 8) * 1.1));
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(centre);
    this.controls.update();
    this.scene = scene;
  }

  // Shows a scene: builds the world when `key` (what is shown) changes, then poses it.
  show(key, data) {
    if (key !== this.key || !this.scene || data.bodies.length !== this.bodies.length) {
      this.build(data);
      this.key = key;
    }
    data.poses.forEach((p, k) => {
      this.bodies[k].position.set(p[0], p[1], p[2]);
      this.bodies[k].quaternion.set(p[4], p[5], p[6], p[3]); // x, y, z, w
    });
    (data.end_effectors ?? []).forEach((p, k) => this.ees[k]?.position.set(p[0], p[1], p[2]));
    this.target.visible = Boolean(data.target);
    if (data.target) this.target.position.set(...data.target);
    this.draw();
  }

  clear() {
    if (this.scene) this.dispose();
    this.key = null;
    this.renderer.clear();
  }

  dispose() {
    this.scene.traverse((o) => { o.geometry?.dispose(); o.material?.dispose(); });
    this.scene = null;
  }

  resize() {
    const w = Math.max(this.container.clientWidth, 1), h = Math.max(this.container.clientHeight, 1);
    this.renderer.setSize(w, h, false);
    this.renderer.domElement.style.width = w + 'px';
    this.renderer.domElement.style.height = h + 'px';
    this.camera.aspect = w / h;
    this.camera.updateProjectionMatrix();
  }

  draw() {
    if (this.scene) this.renderer.render(this.scene, this.camera);
  }
}
