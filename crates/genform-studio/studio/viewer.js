// The model viewer: an orbitable three.js view of a GLB (with an optional translucent target
// mesh), or a flat picture (SVG/PNG) for 2D formalisms. Renders on demand (orbit, resize,
// load), not in a loop, so an idle page costs no CPU.

import * as THREE from 'three';
import { OrbitControls } from 'three/addons/controls/OrbitControls.js';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { h } from './dom.js';

/** One viewer inside `container`; `testid` prefixes the data-testids of its parts. */
export class Viewer {
  constructor(container, { testid = 'viewer' } = {}) {
    this.testid = testid;
    this.root = h('div', { class: 'viewer', testid, dataset: { state: 'empty' } });
    this.canvasHost = h('div', { class: 'viewer-3d' });
    this.picture = h('img', { class: 'viewer-2d', testid: `${testid}-picture`, alt: 'model drawing', hidden: true });
    this.message = h('div', { class: 'viewer-message', testid: `${testid}-message`, text: 'Nothing to show yet.' });
    this.info = h('div', { class: 'viewer-info', testid: `${testid}-info` });
    const reset = h('button', { class: 'ghost', title: 'Frame the model', text: 'Frame', onclick: () => this.frame() });
    this.upButton = h('button', { class: 'ghost', testid: `${testid}-zup`, title: 'Turn +z to the screen\'s up (for meshes made in z-up tools); glTF\'s convention is +y up',
      text: 'Z up', 'aria-pressed': 'false', onclick: () => this.setZUp(!this.zUp) });
    this.tools = h('div', { class: 'viewer-tools' }, this.upButton, reset);
    this.root.append(this.canvasHost, this.picture, this.message, this.info, this.tools);
    this.tools.hidden = true; // shown with a 3D model
    this.zUp = false;
    container.append(this.root);
    this.loader = new GLTFLoader();
    this.renderer = null; // created lazily: WebGL contexts are few and costly
    this.model = null;
    this.target = null;
    this.loadToken = 0;
  }

  ensureRenderer() {
    if (this.renderer) return;
    const renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    renderer.setPixelRatio(Math.min(2, window.devicePixelRatio || 1));
    renderer.setClearColor(0xf4f5f7, 1);
    renderer.domElement.dataset.testid = `${this.testid}-canvas`;
    this.canvasHost.append(renderer.domElement);
    const scene = new THREE.Scene();
    scene.add(new THREE.HemisphereLight(0xffffff, 0x8d8d8d, 2.2));
    const sun = new THREE.DirectionalLight(0xffffff, 2.0);
    sun.position.set(3, 5, 4);
    scene.add(sun);
    const camera = new THREE.PerspectiveCamera(40, 1, 0.01, 10000);
    camera.position.set(3, 2, 5);
    const controls = new OrbitControls(camera, renderer.domElement);
    controls.addEventListener('change', () => this.render());
    controls.addEventListener('start', () => (this.userMoved = true));
    Object.assign(this, { renderer, scene, camera, controls });
    this.grid = null;
    new ResizeObserver(() => this.resize()).observe(this.canvasHost);
    this.resize();
  }

  resize() {
    if (!this.renderer) return;
    const w = this.canvasHost.clientWidth || 400;
    const hgt = this.canvasHost.clientHeight || 300;
    this.renderer.setSize(w, hgt, false);
    this.camera.aspect = w / hgt;
    this.camera.updateProjectionMatrix();
    // Until the user turns the view, keep the model fitted to the new shape.
    if (this.model && !this.userMoved) this.frame();
    else this.render();
  }

  render() {
    if (this.renderer && !this.canvasHost.hidden) this.renderer.render(this.scene, this.camera);
  }

  setState(state, message = '') {
    this.root.dataset.state = state;
    this.message.textContent = message;
    this.message.hidden = !message;
  }

  /** Shows a 2D drawing (SVG or PNG URL) instead of the 3D view. */
  async showPicture(url, info = '') {
    const token = ++this.loadToken;
    this.setState('loading', 'Loading…');
    this.canvasHost.hidden = true;
    this.tools.hidden = true;
    this.picture.hidden = false;
    await new Promise((resolve, reject) => {
      this.picture.onload = resolve;
      this.picture.onerror = () => reject(new Error(`could not load ${url}`));
      this.picture.src = url;
    }).catch((err) => {
      if (token === this.loadToken) this.setState('error', err.message);
      throw err;
    });
    if (token !== this.loadToken) return;
    this.info.textContent = info;
    this.root.dataset.kind = '2d';
    this.setState('loaded');
  }

  /** Loads a GLB into the 3D view, replacing the model; keeps the camera unless `frame`. */
  async showGlb(url, { info = '', frame = true } = {}) {
    const token = ++this.loadToken;
    this.ensureRenderer();
    this.picture.hidden = true;
    this.canvasHost.hidden = false;
    this.tools.hidden = false;
    this.setState('loading', 'Loading…');
    let gltf;
    try {
      gltf = await this.loader.loadAsync(url);
    } catch (err) {
      if (token === this.loadToken) this.setState('error', `Could not load the model: ${err.message || err}`);
      throw err;
    }
    if (token !== this.loadToken) return;
    if (this.model) this.dispose(this.model);
    this.model = gltf.scene;
    this.orient(this.model);
    let triangles = 0;
    this.model.traverse((o) => {
      if (o.isMesh) {
        const g = o.geometry;
        triangles += (g.index ? g.index.count : g.attributes.position.count) / 3;
        if (o.material) o.material.side = THREE.DoubleSide; // grammars emit open surfaces
      }
    });
    this.scene.add(this.model);
    this.root.dataset.triangles = String(Math.round(triangles));
    const size = new THREE.Box3().setFromObject(this.model).getSize(new THREE.Vector3());
    this.root.dataset.size = [size.x, size.y, size.z].map((v) => v.toPrecision(4)).join(','); // as shown, +y up
    this.root.dataset.kind = '3d';
    this.info.textContent = info || `${Math.round(triangles).toLocaleString()} triangles`;
    if (frame || !this.framed) this.frame();
    this.setState('loaded');
    this.render();
  }

  /** Shows (or with null removes) a target mesh as translucent glass around the model. */
  async showTarget(url) {
    this.ensureRenderer();
    if (this.target) {
      this.dispose(this.target);
      this.target = null;
    }
    if (!url) return this.render();
    const gltf = await this.loader.loadAsync(url);
    const glass = new THREE.MeshStandardMaterial({ color: 0x4dabf7, transparent: true, opacity: 0.18, depthWrite: false, side: THREE.DoubleSide });
    gltf.scene.traverse((o) => {
      if (o.isMesh) o.material = glass;
    });
    this.target = gltf.scene;
    this.orient(this.target);
    this.scene.add(this.target);
    this.root.dataset.target = 'shown';
    this.tools.hidden = false;
    if (!this.model) this.frame(); // the model will appear inside it
    this.render();
  }

  /** Turns +z (true) or +y (false, glTF's convention) to the screen's up. */
  setZUp(zUp) {
    this.zUp = zUp;
    this.upButton.setAttribute('aria-pressed', String(zUp));
    this.root.dataset.up = zUp ? 'z' : 'y';
    if (this.model) this.orient(this.model);
    if (this.target) this.orient(this.target);
    if (this.model || this.target) this.frame();
  }

  orient(object) {
    object.rotation.set(this.zUp ? -Math.PI / 2 : 0, 0, 0);
    object.updateMatrixWorld(true);
  }

  /** Points the camera at the model's (and target's) bounding box. */
  frame() {
    if (!this.renderer) return;
    this.userMoved = false;
    const box = new THREE.Box3();
    if (this.model) box.expandByObject(this.model);
    if (this.target) box.expandByObject(this.target);
    if (box.isEmpty()) return;
    const size = box.getSize(new THREE.Vector3());
    const center = box.getCenter(new THREE.Vector3());
    // Fit the box's corners into the view from a 3/4 direction: for each corner, the
    // distance at which it just fits the narrower of the two fields of view.
    const dir = new THREE.Vector3(0.9, 0.6, 1.2).normalize();
    const up = new THREE.Vector3(0, 1, 0);
    const right = new THREE.Vector3().crossVectors(up, dir).normalize();
    const camUp = new THREE.Vector3().crossVectors(dir, right);
    const tanV = Math.tan((this.camera.fov * Math.PI) / 360);
    const tanH = tanV * this.camera.aspect;
    let dist = 1e-3;
    for (let i = 0; i < 8; i++) {
      const corner = new THREE.Vector3(i & 1 ? box.max.x : box.min.x, i & 2 ? box.max.y : box.min.y, i & 4 ? box.max.z : box.min.z).sub(center);
      const z = corner.dot(dir);
      dist = Math.max(dist, z + Math.abs(corner.dot(right)) / tanH, z + Math.abs(corner.dot(camUp)) / tanV);
    }
    dist *= 1.1;
    this.camera.position.copy(center).addScaledVector(dir, dist);
    this.camera.near = dist / 100;
    this.camera.far = dist * 100;
    this.camera.updateProjectionMatrix();
    this.controls.target.copy(center);
    this.controls.update();
    if (this.grid) {
      this.scene.remove(this.grid);
      this.grid.geometry.dispose();
    }
    const span = Math.max(size.x, size.z, 1e-3) * 2;
    this.grid = new THREE.GridHelper(span, 20, 0xb8bcc4, 0xdfe2e6);
    this.grid.position.set(center.x, box.min.y, center.z);
    this.scene.add(this.grid);
    this.framed = true;
    this.render();
  }

  dispose(object) {
    this.scene.remove(object);
    object.traverse((o) => {
      if (o.geometry) o.geometry.dispose();
      if (o.material) [].concat(o.material).forEach((m) => m.dispose());
    });
  }

  /** Marks the model shown as out of date (`stale`: the source it came from
   * no longer compiles), dimmed with a note, or as current again. */
  setStale(stale, note = 'last good model: the grammar has errors') {
    if (stale) this.root.dataset.stale = note;
    else delete this.root.dataset.stale;
  }

  /** Empties the view. */
  clear(message = 'Nothing to show yet.') {
    this.setStale(false);
    this.loadToken++;
    if (this.model) this.dispose(this.model);
    if (this.target) this.dispose(this.target);
    this.model = this.target = null;
    this.framed = false;
    this.userMoved = false;
    this.picture.hidden = true;
    this.tools.hidden = true;
    this.info.textContent = '';
    delete this.root.dataset.target;
    this.setState('empty', message);
    this.render();
  }
}
