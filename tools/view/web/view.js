// tumble-view's page: the frames from /ws drawn with three.js (Z up, the
// world frame W of tumbled) and the health in the panel.
'use strict';

const STATE_NAMES = ['WAITING FOR SENSORS', 'INITIALISING', 'TRACKING', 'DEGRADED', 'LOST'];
const NO_TRAFFIC_AFTER_S = 3;
const MAX_TRAJECTORY_POSES = 20000;

// What the page has drawn, for a person at the console and for the browser test.
const view = window.tumbleView = {
  connected: false, poses: 0, scans: 0, scanPoints: 0, mapPoints: 0, statusMessages: 0, lastScanIndex: -1,
};

// --- scene
const container = document.getElementById('scene');
const renderer = new THREE.WebGLRenderer({ antialias: false });
renderer.setPixelRatio(window.devicePixelRatio || 1);
renderer.setClearColor(0x101418);
container.appendChild(renderer.domElement);
const scene = new THREE.Scene();
const camera = new THREE.PerspectiveCamera(60, 1, 0.05, 2000);
camera.up.set(0, 0, 1);
camera.position.set(-8, -8, 6);
const controls = new THREE.OrbitControls(camera, renderer.domElement);
controls.target.set(0, 0, 0);
scene.add(new THREE.AxesHelper(0.5));  // the world origin

const trajectoryPositions = new Float32Array(3 * MAX_TRAJECTORY_POSES);
const trajectoryGeometry = new THREE.BufferGeometry();
trajectoryGeometry.setAttribute('position', new THREE.BufferAttribute(trajectoryPositions, 3));
trajectoryGeometry.setDrawRange(0, 0);
scene.add(new THREE.Line(trajectoryGeometry, new THREE.LineBasicMaterial({ color: 0xffe14d })));
let trajectoryCount = 0;

const poseAxes = new THREE.AxesHelper(1.0);  // x red, y green, z blue: the lidar frame L
poseAxes.visible = false;
scene.add(poseAxes);

function pointCloud(size, vertexColors, color) {
  const geometry = new THREE.BufferGeometry();
  const material = new THREE.PointsMaterial({ size: size, sizeAttenuation: false,
    vertexColors: vertexColors ? THREE.VertexColors : THREE.NoColors, color: color });
  const points = new THREE.Points(geometry, material);
  points.frustumCulled = false;
  scene.add(points);
  return points;
}
const scanCloud = pointCloud(3, true, 0xffffff);
const mapCloud = pointCloud(1.5, false, 0x6f7f8f);
let lastScan = null;

function resize() {
  const w = container.clientWidth, h = container.clientHeight;
  renderer.setSize(w, h);
  camera.aspect = w / Math.max(h, 1);
  camera.updateProjectionMatrix();
}
window.addEventListener('resize', resize);
resize();

function animate() {
  controls.update();
  renderer.render(scene, camera);
  requestAnimationFrame(animate);
}
requestAnimationFrame(animate);

// --- trajectory and pose
function clearTrajectory() {
  trajectoryCount = 0;
  trajectoryGeometry.setDrawRange(0, 0);
}

function appendTrajectory(x, y, z) {
  if (trajectoryCount === MAX_TRAJECTORY_POSES) {  // keep the newest half
    trajectoryPositions.copyWithin(0, 3 * MAX_TRAJECTORY_POSES / 2);
    trajectoryCount = MAX_TRAJECTORY_POSES / 2;
  }
  trajectoryPositions.set([x, y, z], 3 * trajectoryCount);
  trajectoryCount += 1;
  trajectoryGeometry.setDrawRange(0, trajectoryCount);
  trajectoryGeometry.attributes.position.needsUpdate = true;
  trajectoryGeometry.computeBoundingSphere();
}

function followPose(p) {
  const delta = new THREE.Vector3(p[0], p[1], p[2]).sub(controls.target);
  controls.target.add(delta);
  camera.position.add(delta);
}

function showPose(p, q) {
  poseAxes.visible = true;
  poseAxes.position.set(p[0], p[1], p[2]);
  poseAxes.quaternion.set(q[1], q[2], q[3], q[0]);
  document.getElementById('pose').textContent =
    `x ${p[0].toFixed(2)} m  y ${p[1].toFixed(2)} m  z ${p[2].toFixed(2)} m`;
}

function onPose(m) {
  if (m.scan_index < view.lastScanIndex) clearTrajectory();  // tumbled restarted
  view.lastScanIndex = m.scan_index;
  view.poses += 1;
  appendTrajectory(m.p[0], m.p[1], m.p[2]);
  showPose(m.p, m.q);
  followPose(m.p);
  const error = m.expected_error_m === null ? '–' : `${(100 * m.expected_error_m).toFixed(1)} cm`;
  document.getElementById('expected-error').textContent =
    `expected error ${error}, ${m.registered ? 'registered' : 'not registered'}, ` +
    `inliers ${m.inlier_ratio === null ? '–' : (100 * m.inlier_ratio).toFixed(0) + ' %'}, scan ${m.scan_index}`;
}

function onHistory(m) {
  clearTrajectory();
  for (let i = 0; i + 2 < m.p.length; i += 3) appendTrajectory(m.p[i], m.p[i + 1], m.p[i + 2]);
}

// --- points
function hueColour(t, out, i) {  // t in [0, 1]: red (0) through yellow to green and blue (1)
  const c = new THREE.Color().setHSL(0.66 * Math.min(Math.max(t, 0), 1), 1.0, 0.5);
  out[3 * i] = c.r; out[3 * i + 1] = c.g; out[3 * i + 2] = c.b;
}

const LEGENDS = {
  weight: 'blue: trusted (weight 1, the scan\'s largest) … red: distrusted (0)',
  sigma: 'blue: σs 0 … red: σs 10 cm or more (skew uncertainty)',
  height: 'red: lowest … blue: highest point of the scan',
  ring: 'red: ring 0 (lowest laser) … blue: ring 15',
};

function colourScan() {
  const mode = document.querySelector('input[name=colour]:checked').value;
  document.getElementById('colour-legend').textContent = LEGENDS[mode];
  if (!lastScan) return;
  const s = lastScan, n = s.n;
  const colours = new Float32Array(3 * n);
  let zmin = Infinity, zmax = -Infinity;
  for (let i = 0; i < n; i++) { zmin = Math.min(zmin, s.z[i]); zmax = Math.max(zmax, s.z[i]); }
  for (let i = 0; i < n; i++) {
    let t;
    if (mode === 'weight') t = s.weight[i];                 // trusted: blue, distrusted: red
    else if (mode === 'sigma') t = 1 - s.sigma[i] / 0.1;    // sigma_s 0: blue, 10 cm and more: red
    else if (mode === 'height') t = (s.z[i] - zmin) / Math.max(zmax - zmin, 1e-3);
    else t = (s.ring[i] % 16) / 15;
    hueColour(t, colours, i);
  }
  scanCloud.geometry.setAttribute('color', new THREE.BufferAttribute(colours, 3));
}
document.querySelectorAll('input[name=colour]').forEach(e => e.addEventListener('change', colourScan));
colourScan();

function floats(buffer, field, n) { return new Float32Array(buffer, 16 + 4 * n * field, n); }

function onBinary(buffer) {
  const header = new DataView(buffer, 0, 16);
  const magic = String.fromCharCode(header.getUint8(0), header.getUint8(1), header.getUint8(2), header.getUint8(3));
  const n = header.getUint32(4, true);
  if (magic === 'SCAN') {
    const positions = new Float32Array(3 * n);
    const x = floats(buffer, 0, n), y = floats(buffer, 1, n), z = floats(buffer, 2, n);
    for (let i = 0; i < n; i++) { positions[3 * i] = x[i]; positions[3 * i + 1] = y[i]; positions[3 * i + 2] = z[i]; }
    lastScan = { n: n, z: z, sigma: floats(buffer, 3, n), weight: floats(buffer, 4, n), ring: floats(buffer, 5, n) };
    scanCloud.geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    colourScan();
    view.scans += 1;
    view.scanPoints = n;
    const stride = header.getUint32(12, true);
    document.getElementById('scan-info').textContent =
      `scan ${header.getUint32(8, true)}: ${n} points${stride > 1 ? ` (every ${stride}th)` : ''}`;
  } else if (magic === 'MAP_') {
    const positions = new Float32Array(3 * n);
    const x = floats(buffer, 0, n), y = floats(buffer, 1, n), z = floats(buffer, 2, n);
    for (let i = 0; i < n; i++) { positions[3 * i] = x[i]; positions[3 * i + 1] = y[i]; positions[3 * i + 2] = z[i]; }
    mapCloud.geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
    view.mapPoints = n;
    document.getElementById('map-info').textContent =
      `local map: ${header.getUint32(8, true)} points, ${n} drawn`;
  }
}

// --- panel
function fill(tableId, rows) {
  const table = document.getElementById(tableId);
  table.replaceChildren(...rows.map(([name, value, nonzero]) => {
    const tr = document.createElement('tr');
    if (nonzero) tr.className = 'nonzero';
    for (const text of [name, value]) {
      const td = document.createElement('td');
      td.textContent = text;
      tr.appendChild(td);
    }
    return tr;
  }));
}

const fixed = (v, digits) => (v === null ? '–' : v.toFixed(digits));

function showState(className, name, reason) {
  const e = document.getElementById('state');
  e.className = className;
  e.dataset.state = name;
  document.getElementById('state-name').textContent = name;
  document.getElementById('state-reason').textContent = reason;
}

function onStatus(m) {
  view.statusMessages += 1;
  view.status = m;
  showState(`state-${m.state}`, STATE_NAMES[m.state] || m.state_name, m.reason || m.state_name);
  fill('rates', Object.entries(m.rates).map(([k, v]) => [k, fixed(v, 1)]));
  fill('stages', m.stages.map(([name, median, max]) => [name, `${fixed(median, 2)} / ${fixed(max, 2)}`]));
  fill('latency', Object.entries(m.latency).map(([k, v]) => [k, fixed(v, 2)])
    .concat([['expected error max (cm)', m.expected_error_max_m === null ? '–' : fixed(100 * m.expected_error_max_m, 1)],
             ['resets', String(m.resets)], ['uptime (s)', fixed(m.uptime_s, 0)]]));
  const counters = Object.entries(m.counters).map(([k, v]) => [k, String(v),
    v !== 0 && !['lidar_packets', 'imu_frames', 'scans_registered'].includes(k)]);
  for (const [name, fillRatio, drops] of m.rings) counters.push([`ring ${name}: fill / drops`, `${fixed(fillRatio, 2)} / ${drops}`, drops !== 0]);
  fill('counters', counters);
}

function showBanner(text) {
  const banner = document.getElementById('banner');
  banner.hidden = !text;
  banner.textContent = text || '';
}

function onLink(m) {
  const since = m.since_last_s;
  document.getElementById('link').textContent =
    `${m.lcm_url}, channels ${m.channel_prefix}*: ${m.messages} messages` +
    (since === null ? '' : `, newest ${since.toFixed(1)} s ago`) + `; ${m.browsers} browser(s)`;
  if (since === null || since > NO_TRAFFIC_AFTER_S) {
    showState('state-unknown', 'NO DATA', since === null ? 'no LCM message from tumbled yet' :
      `no LCM message from tumbled for ${since.toFixed(0)} s`);
    showBanner(`No LCM traffic on ${m.lcm_url} (channels ${m.channel_prefix}*). Likely causes:\n` +
      '• tumbled is not running, or publishes under another lcm.channel_prefix;\n' +
      '• ttl=0 in the URL keeps messages on tumbled\'s own host: run the view there, or set ttl=1 on both;\n' +
      '• no multicast route: ip route add 224.0.0.0/4 dev <interface> (dev lo on one host with no network);\n' +
      '• a firewall dropping UDP to the LCM port.');
  } else {
    showBanner('');
  }
}

// --- connection
function connect() {
  const ws = new WebSocket(`${location.protocol === 'https:' ? 'wss' : 'ws'}://${location.host}/ws`);
  ws.binaryType = 'arraybuffer';
  ws.onopen = () => { view.connected = true; showBanner(''); };
  ws.onmessage = (event) => {
    if (typeof event.data !== 'string') return onBinary(event.data);
    const m = JSON.parse(event.data);
    if (m.type === 'status') onStatus(m);
    else if (m.type === 'pose') onPose(m);
    else if (m.type === 'odometry') showPose(m.p, m.q);
    else if (m.type === 'link') onLink(m);
    else if (m.type === 'history') onHistory(m);
  };
  ws.onclose = () => {
    view.connected = false;
    showState('state-unknown', 'DISCONNECTED', 'the view\'s server is unreachable: reconnecting');
    showBanner(`Lost the connection to tumble-view at ${location.host}: retrying every second.`);
    setTimeout(connect, 1000);
  };
}
connect();
