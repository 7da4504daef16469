// path_view_3d.cpp — the run report's interactive 3D tool path (see path_view_3d.hpp): the
// thinning, the binary path record, and the markup with its small script.
#include "report/path_view_3d.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "report/inline_blob.hpp"

#ifndef PCNC_THREE_JS_DIR
#define PCNC_THREE_JS_DIR "/usr/share/javascript/three"
#endif

namespace pcnc {

namespace {

// ---- the record ----

template <typename T>
void put(std::string& out, T v) {
  char b[sizeof(T)];
  std::memcpy(b, &v, sizeof(T));  // little-endian hosts only (x86-64, arm64): as the trace
  out.append(b, sizeof(T));
}

template <typename T>
T get(const std::string& in, std::size_t& at) {
  if (at + sizeof(T) > in.size()) throw std::runtime_error("path record: cut short");
  T v;
  std::memcpy(&v, in.data() + at, sizeof(T));
  at += sizeof(T);
  return v;
}

template <typename T>
T saturate(double v) {
  const double lo = static_cast<double>(std::numeric_limits<T>::min());
  const double hi = static_cast<double>(std::numeric_limits<T>::max());
  return static_cast<T>(std::llround(std::clamp(v, lo, hi)));
}

constexpr std::uint32_t kRecordVersion = 1;

// ---- the page ----

std::string read_file(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return {};
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

// Plain ES2017, no modules: three.js r111 and its OrbitControls are classic scripts that set
// window.THREE. The page sets data-* attributes on #view3d that scripts and the tests read:
// state (loading|ready|error), points, frames drawn, index of the dot's point, lit (pixels not
// background), red (pixels of the dot), load-ms.
const char* kScript = R"JS((function () {
  'use strict';
  var root = document.getElementById('view3d');
  var start = performance.now();
  document.body.classList.add('js');
  function fail(msg) {
    root.dataset.state = 'error';
    document.body.classList.remove('has3d');
    root.querySelector('.v3-msg').textContent = 'Interactive view not shown: ' + msg + ' The static view below shows the same path.';
  }
  function inflate(id) {
    var s = atob(document.getElementById(id).textContent.trim());
    var u = new Uint8Array(s.length);
    for (var i = 0; i < s.length; i++) u[i] = s.charCodeAt(i);
    return new Response(new Blob([u]).stream().pipeThrough(new DecompressionStream('gzip'))).arrayBuffer();
  }
  function decode(buf) {
    var v = new DataView(buf), o = 0, i, k;
    if (String.fromCharCode(v.getUint8(0), v.getUint8(1), v.getUint8(2), v.getUint8(3)) !== 'PV3D' || v.getUint32(4, true) !== 1) {
      throw new Error('the path record is not version 1');
    }
    var n = v.getUint32(8, true);
    var origin = [v.getFloat64(12, true), v.getFloat64(20, true), v.getFloat64(28, true)];
    var q = v.getFloat64(36, true), tick = v.getFloat64(44, true);
    o = 52;
    var d = {n: n, P: new Float64Array(3 * n), T: new Float64Array(n), L: new Uint32Array(n), S: new Float32Array(n),
             F: new Float32Array(3 * n), R: new Uint8Array(n)};
    for (k = 0; k < 3; k++) {
      var acc = 0;
      for (i = 0; i < n; i++, o += 4) { acc += v.getInt32(o, true); d.P[3 * i + k] = origin[k] + acc * q; }
    }
    var t = 0, line = 0;
    for (i = 0; i < n; i++, o += 4) { t += v.getUint32(o, true); d.T[i] = t * tick; }
    for (i = 0; i < n; i++, o += 4) { line += v.getInt32(o, true); d.L[i] = line; }
    for (i = 0; i < n; i++, o += 2) d.S[i] = v.getUint16(o, true) / 100;
    for (k = 0; k < 3; k++) for (i = 0; i < n; i++, o += 2) d.F[3 * i + k] = v.getInt16(o, true) * 1e-4;
    for (i = 0; i < n; i++, o += 1) d.R[i] = v.getUint8(o);
    return d;
  }
  var VIRIDIS = [[68,1,84],[72,40,120],[62,73,137],[49,104,142],[38,130,142],[31,158,137],[53,183,121],[110,206,88],[181,222,43],[253,231,37]];
  function viridis(f) {
    f = Math.min(1, Math.max(0, f)) * (VIRIDIS.length - 1);
    var i = Math.min(Math.floor(f), VIRIDIS.length - 2), w = f - i;
    return VIRIDIS[i].map(function (c, k) { return (c * (1 - w) + VIRIDIS[i + 1][k] * w) / 255; });
  }
  function text(id, s) { document.getElementById(id).textContent = s; }
  async function run() {
    if (typeof DecompressionStream === 'undefined') return fail('this browser cannot unpack it (no DecompressionStream).');
    var lib = document.createElement('script');
    lib.textContent = new TextDecoder().decode(await inflate('v3-lib'));
    document.head.appendChild(lib);
    if (!window.THREE || !THREE.OrbitControls) return fail('three.js did not load.');
    var d = decode(await inflate('v3-data')), n = d.n, i, k;
    if (n < 2) return fail('the trace has no tool path.');
    var canvas = root.querySelector('canvas'), renderer;
    try {
      renderer = new THREE.WebGLRenderer({canvas: canvas, antialias: true, preserveDrawingBuffer: true});
    } catch (e) { return fail('WebGL is not available (' + e.message + ').'); }
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    renderer.setClearColor(0x161a24);
    var lo = [Infinity, Infinity, Infinity], hi = [-Infinity, -Infinity, -Infinity], vmax = 0;
    for (i = 0; i < n; i++) {
      for (k = 0; k < 3; k++) { lo[k] = Math.min(lo[k], d.P[3 * i + k]); hi[k] = Math.max(hi[k], d.P[3 * i + k]); }
      if (!d.R[i]) vmax = Math.max(vmax, d.S[i]);
    }
    if (vmax <= 0) vmax = 1;
    var c = [0, 1, 2].map(function (k) { return (lo[k] + hi[k]) / 2; });
    var size = Math.max(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2], 1e-3);
    var pos = new Float32Array(3 * n), col = new Float32Array(3 * n);
    for (i = 0; i < n; i++) {
      var rgb = d.R[i] ? [0.67, 0.70, 0.77] : viridis(d.S[i] / vmax);
      for (k = 0; k < 3; k++) { pos[3 * i + k] = d.P[3 * i + k] - c[k]; col[3 * i + k] = rgb[k]; }
    }
    var geometry = new THREE.BufferGeometry();
    geometry.setAttribute('position', new THREE.BufferAttribute(pos, 3));
    geometry.setAttribute('color', new THREE.BufferAttribute(col, 3));
    var scene = new THREE.Scene();
    scene.add(new THREE.Line(geometry, new THREE.LineBasicMaterial({vertexColors: THREE.VertexColors})));
    var box = new THREE.Box3(new THREE.Vector3(lo[0] - c[0], lo[1] - c[1], lo[2] - c[2]),
                             new THREE.Vector3(hi[0] - c[0], hi[1] - c[1], hi[2] - c[2]));
    scene.add(new THREE.Box3Helper(box, 0x3b4358));
    var dot = new THREE.Mesh(new THREE.SphereBufferGeometry(size * 0.012, 20, 14), new THREE.MeshBasicMaterial({color: 0xff2d2d}));
    scene.add(dot);
    var camera = new THREE.PerspectiveCamera(35, 1, size * 0.01, size * 100);
    camera.up.set(0, 0, 1);
    camera.position.set(size * 1.5, -size * 1.9, size * 1.4);
    var controls = new THREE.OrbitControls(camera, canvas);
    controls.target.set(0, 0, 0);
    controls.update();
    var frames = 0;
    function draw() {
      var w = canvas.clientWidth || 760, h = canvas.clientHeight || 480;
      renderer.setSize(w, h, false);
      camera.aspect = w / h;
      camera.updateProjectionMatrix();
      renderer.render(scene, camera);
      root.dataset.frames = ++frames;
    }
    controls.addEventListener('change', draw);
    window.addEventListener('resize', draw);
    var slider = document.getElementById('v3-slider'), tEnd = d.T[n - 1];
    function show() {
      var t = Number(slider.value) / Number(slider.max) * tEnd, a = 0, b = n - 1;
      while (a < b) { var m = (a + b + 1) >> 1; if (d.T[m] <= t) a = m; else b = m - 1; }
      var j = Math.min(a + 1, n - 1), w = j > a && d.T[j] > d.T[a] ? (t - d.T[a]) / (d.T[j] - d.T[a]) : 0;
      dot.position.set(pos[3 * a] * (1 - w) + pos[3 * j] * w, pos[3 * a + 1] * (1 - w) + pos[3 * j + 1] * w,
                       pos[3 * a + 2] * (1 - w) + pos[3 * j + 2] * w);
      root.dataset.index = a;
      text('v3-time', t.toFixed(3) + ' s');
      text('v3-line', String(d.L[a]));
      text('v3-speed', d.S[a].toFixed(2) + ' mm/s (' + (d.S[a] * 60).toFixed(0) + ' mm/min)' + (d.R[a] ? ', rapid' : ''));
      text('v3-ferr', 'X ' + (d.F[3 * a] * 1000).toFixed(1) + ' Y ' + (d.F[3 * a + 1] * 1000).toFixed(1) + ' Z ' +
                      (d.F[3 * a + 2] * 1000).toFixed(1) + ' µm');
      draw();
    }
    slider.addEventListener('input', show);
    var m = /[#&]t=([0-9.]+)/.exec(location.hash);
    if (m) slider.value = Math.round(Math.min(1, parseFloat(m[1])) * Number(slider.max));
    root.dataset.state = 'ready';
    document.body.classList.add('has3d');
    show();
    var gl = renderer.getContext(), w = gl.drawingBufferWidth, h = gl.drawingBufferHeight, px = new Uint8Array(4 * w * h);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
    var lit = 0, red = 0;
    for (i = 0; i < w * h; i++) {
      var r = px[4 * i], g = px[4 * i + 1], bl = px[4 * i + 2];
      if (Math.abs(r - 0x16) + Math.abs(g - 0x1a) + Math.abs(bl - 0x24) > 24) lit++;
      if (r > 200 && g < 90 && bl < 90) red++;
    }
    root.dataset.lit = lit;
    root.dataset.red = red;
    root.dataset.loadMs = (performance.now() - start).toFixed(0);
  }
  run().catch(function (e) { fail(e.message + '.'); });
})();
)JS";

}  // namespace

std::vector<ToolPathPoint> thin_for_view(const std::vector<ToolPathPoint>& path, std::size_t max_points) {
  max_points = std::max<std::size_t>(max_points, 2);
  if (path.size() <= max_points) return path;
  // Start from the mean step and double until the points fit.
  double length = 0.0;
  for (std::size_t i = 1; i < path.size(); ++i) length += norm(path[i].p - path[i - 1].p);
  double tol = std::max(length / static_cast<double>(max_points), 1e-6);
  for (;;) {
    std::vector<ToolPathPoint> kept;
    kept.reserve(max_points + 1);
    for (std::size_t i = 0; i < path.size(); ++i) {
      const bool last = i + 1 == path.size();
      if (!kept.empty() && !last && path[i].rapid == kept.back().rapid && norm(path[i].p - kept.back().p) < tol) continue;
      kept.push_back(path[i]);
      if (kept.size() > max_points) break;
    }
    if (kept.size() <= max_points) return kept;
    tol *= 2.0;
  }
}

std::string encode_path_record(const std::vector<ToolPathPoint>& points, const PathView3dOptions& options) {
  const std::size_t n = points.size();
  const Vec3 origin = n ? points.front().p : Vec3{};
  std::string out;
  out.reserve(52 + n * 31);
  out.append("PV3D", 4);
  put<std::uint32_t>(out, kRecordVersion);
  put<std::uint32_t>(out, static_cast<std::uint32_t>(n));
  for (std::size_t k = 0; k < 3; ++k) put<double>(out, origin[k]);
  put<double>(out, options.quantum_mm);
  put<double>(out, options.tick_s);
  for (std::size_t k = 0; k < 3; ++k) {
    std::int64_t prev = 0;
    for (const ToolPathPoint& q : points) {
      const auto v = static_cast<std::int64_t>(std::llround((q.p[k] - origin[k]) / options.quantum_mm));
      put<std::int32_t>(out, static_cast<std::int32_t>(v - prev));
      prev = v;
    }
  }
  std::int64_t prev_tick = 0;
  for (const ToolPathPoint& q : points) {
    const std::int64_t tick = std::max<std::int64_t>(std::llround(std::max(q.t, 0.0) / options.tick_s), prev_tick);
    put<std::uint32_t>(out, static_cast<std::uint32_t>(tick - prev_tick));
    prev_tick = tick;
  }
  std::int64_t prev_line = 0;
  for (const ToolPathPoint& q : points) {
    put<std::int32_t>(out, static_cast<std::int32_t>(static_cast<std::int64_t>(q.line) - prev_line));
    prev_line = q.line;
  }
  for (const ToolPathPoint& q : points) put<std::uint16_t>(out, saturate<std::uint16_t>(q.speed * 100.0));
  for (std::size_t k = 0; k < 3; ++k) {
    for (const ToolPathPoint& q : points) put<std::int16_t>(out, saturate<std::int16_t>(q.ferr[k] * 1e4));
  }
  for (const ToolPathPoint& q : points) put<std::uint8_t>(out, q.rapid ? 1 : 0);
  return out;
}

std::vector<ToolPathPoint> decode_path_record(const std::string& record) {
  std::size_t at = 0;
  if (record.compare(0, 4, "PV3D") != 0) throw std::runtime_error("path record: bad magic");
  at = 4;
  if (get<std::uint32_t>(record, at) != kRecordVersion) throw std::runtime_error("path record: unknown version");
  const std::uint32_t n = get<std::uint32_t>(record, at);
  Vec3 origin;
  for (std::size_t k = 0; k < 3; ++k) origin[k] = get<double>(record, at);
  const double q = get<double>(record, at), tick = get<double>(record, at);
  std::vector<ToolPathPoint> pts(n);
  for (std::size_t k = 0; k < 3; ++k) {
    std::int64_t acc = 0;
    for (auto& p : pts) {
      acc += get<std::int32_t>(record, at);
      p.p[k] = origin[k] + static_cast<double>(acc) * q;
    }
  }
  std::int64_t t = 0, line = 0;
  for (auto& p : pts) p.t = static_cast<double>(t += get<std::uint32_t>(record, at)) * tick;
  for (auto& p : pts) p.line = static_cast<std::uint32_t>(line += get<std::int32_t>(record, at));
  for (auto& p : pts) p.speed = get<std::uint16_t>(record, at) / 100.0;
  for (std::size_t k = 0; k < 3; ++k) {
    for (auto& p : pts) p.ferr[k] = get<std::int16_t>(record, at) * 1e-4;
  }
  for (auto& p : pts) p.rapid = get<std::uint8_t>(record, at) != 0;
  if (at != record.size()) throw std::runtime_error("path record: trailing bytes");
  return pts;
}

PackedLibrary pack_three_js(const std::string& three_dir) {
  const std::string dir = three_dir.empty() ? PCNC_THREE_JS_DIR : three_dir;
  const std::string three = read_file(dir + "/three.min.js");
  const std::string orbit = read_file(dir + "/examples/js/controls/OrbitControls.js");
  if (three.empty() || orbit.empty()) return {{}, "three.js was not found in " + dir + " (Debian package libjs-three)"};
  return {base64_encode(gzip_bytes(three + "\n" + orbit)), {}};
}

std::string render_path_view_3d(const std::vector<ToolPathPoint>& path, const PathView3dOptions& options,
                                std::string* why_not) {
  PackedLibrary own;
  if (!options.library.valid()) own = pack_three_js(options.three_dir);
  const PackedLibrary& library = options.library.valid() ? options.library.get() : own;
  if (library.base64.empty()) {
    if (why_not) *why_not = library.why_not;
    return {};
  }
  const std::vector<ToolPathPoint> points = thin_for_view(path, options.max_points);
  std::ostringstream o;
  o << "<div class=\"view3d\" id=\"view3d\" data-state=\"loading\" data-points=\"" << points.size() << "\">\n"
    << "<canvas class=\"v3-canvas\" aria-label=\"tool path, interactive 3D view\"></canvas>\n"
    << "<div class=\"v3-bar\"><input type=\"range\" id=\"v3-slider\" min=\"0\" max=\"2000\" value=\"2000\" "
       "aria-label=\"program time\">\n"
    << "<span class=\"v3-read\">t <b id=\"v3-time\">–</b> · line <b id=\"v3-line\">–</b> · <b id=\"v3-speed\">–</b>"
       " · following error <b id=\"v3-ferr\">–</b></span></div>\n"
    << "<p class=\"v3-msg\">Drag to rotate, scroll to zoom, right-drag to pan. The slider moves the red dot through "
       "program time; "
    << points.size() << " points of the measured path.</p>\n</div>\n";
  o << "<script type=\"application/octet-stream\" id=\"v3-lib\">" << library.base64 << "</script>\n";
  o << "<script type=\"application/octet-stream\" id=\"v3-data\">"
    << base64_encode(gzip_bytes(encode_path_record(points, options))) << "</script>\n";
  o << "<script>\n" << kScript << "</script>\n";
  return o.str();
}

const char* path_view_3d_css() {
  return R"(.view3d{display:none}
body.js .view3d{display:block}
body.has3d .toolpath-static{display:none}
.v3-canvas{display:block;width:100%;height:480px;border-radius:6px;cursor:grab}
.v3-bar{display:flex;gap:10px;align-items:center;flex-wrap:wrap;margin:6px 8px;color:#c9d0de;font-size:12.5px}
.v3-bar input{flex:1 1 240px}
.v3-read b{color:#fff;font-weight:600;font-variant-numeric:tabular-nums}
@media print{.view3d{display:none!important}.toolpath-static{display:block!important}}
)";
}

}  // namespace pcnc
