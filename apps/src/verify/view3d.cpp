// SPDX-License-Identifier: Apache-2.0
#include "verify/view3d.h"

#include <fmt/format.h>
#include <morph/exceptions.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "verify/html.h"

namespace morphmill {

namespace {

template <class T>
std::string base64_of(const std::vector<T>& values) {
  std::string bytes(values.size() * sizeof(T), '\0');
  if (!values.empty()) std::memcpy(bytes.data(), values.data(), bytes.size());
  return base64(bytes);
}

// Text that may sit inside a <script> element.
std::string script_safe(std::string text) {
  for (std::size_t at = text.find("</"); at != std::string::npos; at = text.find("</", at + 3))
    text.replace(at, 2, "<\\/");
  return text;
}

const char* kViewerScript = R"JS(
(function () {
  var section = document.getElementById('view3d');
  function fail(why) {
    section.setAttribute('data-view3d', 'failed: ' + why);
    document.getElementById('view3d-readout').textContent = '3D view unavailable: ' + why;
  }
  if (!window.THREE || !THREE.OrbitControls) { fail('three.js did not load'); return; }
  function decode(text, Type) {
    var s = atob(text), bytes = new Uint8Array(s.length);
    for (var i = 0; i < s.length; i++) bytes[i] = s.charCodeAt(i);
    return new Type(bytes.buffer);
  }
  var D = JSON.parse(document.getElementById('view3d-data').textContent);
  var positions = decode(D.positions, Float32Array), indices = decode(D.indices, Uint32Array);
  var colours = decode(D.colours, Uint8Array), values = decode(D.values, Float64Array);
  var moves = decode(D.moves, Int32Array), lines = decode(D.lines, Int32Array);
  var canvasBox = document.getElementById('view3d-canvas');
  var renderer;
  try { renderer = new THREE.WebGLRenderer({antialias: true, preserveDrawingBuffer: true}); }
  catch (e) { fail('WebGL is not available (' + e.message + ')'); return; }
  var width = canvasBox.clientWidth || 900, height = canvasBox.clientHeight || 600;
  renderer.setPixelRatio(window.devicePixelRatio || 1);
  renderer.setSize(width, height);
  renderer.setClearColor(0xffffff);
  canvasBox.appendChild(renderer.domElement);
  var geometry = new THREE.BufferGeometry();
  geometry.setAttribute('position', new THREE.BufferAttribute(positions, 3));
  geometry.setAttribute('color', new THREE.BufferAttribute(colours, 3, true));
  geometry.setIndex(new THREE.BufferAttribute(indices, 1));
  geometry.computeBoundingSphere();
  var material = new THREE.MeshPhongMaterial({vertexColors: THREE.VertexColors, flatShading: true,
                                              shininess: 0, side: THREE.DoubleSide});
  var part = new THREE.Mesh(geometry, material);
  var scene = new THREE.Scene();
  scene.add(part);
  scene.add(new THREE.AmbientLight(0xffffff, 0.45));
  var camera = new THREE.PerspectiveCamera(35, width / height, 1e-3, 1e6);
  var headlight = new THREE.DirectionalLight(0xffffff, 0.6);
  camera.add(headlight);
  scene.add(camera);
  var radius = geometry.boundingSphere.radius || 1;
  camera.near = radius / 1000; camera.far = radius * 100; camera.updateProjectionMatrix();
  camera.up.set(0, 0, 1);
  camera.position.set(2.2 * radius, -2.2 * radius, 1.8 * radius);
  var controls = new THREE.OrbitControls(camera, renderer.domElement);
  controls.target.set(0, 0, 0);
  controls.update();
  var frames = 0;
  function draw() { renderer.render(scene, camera); frames++; }
  controls.addEventListener('change', draw);
  var marker = new THREE.Mesh(new THREE.SphereBufferGeometry(radius / 150, 12, 8),
                              new THREE.MeshBasicMaterial({color: 0x000000}));
  marker.visible = false;
  scene.add(marker);
  var readout = document.getElementById('view3d-readout');
  var raycaster = new THREE.Raycaster(), mouse = new THREE.Vector2();
  var triangle = new THREE.Triangle(), bary = new THREE.Vector3();
  var A = new THREE.Vector3(), B = new THREE.Vector3(), C = new THREE.Vector3();
  function kind(d) { return d < D.band[0] ? 'gouge' : d > D.band[1] ? 'excess' : 'within the band'; }
  function pick(clientX, clientY) {
    var rect = renderer.domElement.getBoundingClientRect();
    mouse.x = ((clientX - rect.left) / rect.width) * 2 - 1;
    mouse.y = -((clientY - rect.top) / rect.height) * 2 + 1;
    raycaster.setFromCamera(mouse, camera);
    var hits = raycaster.intersectObject(part);
    if (!hits.length) { readout.textContent = 'No surface under the pointer.'; return null; }
    var hit = hits[0], f = hit.face;
    A.fromArray(positions, 3 * f.a); B.fromArray(positions, 3 * f.b); C.fromArray(positions, 3 * f.c);
    triangle.set(A, B, C);
    triangle.getBarycoord(hit.point, bary);
    var d = bary.x * values[f.a] + bary.y * values[f.b] + bary.z * values[f.c];
    var t = hit.faceIndex, p = hit.point;
    var at = [p.x + D.center[0], p.y + D.center[1], p.z + D.center[2]];
    var made = moves[t] >= 0 ? 'made by move ' + moves[t] + (lines[t] > 0 ? ' (G-code line ' + lines[t] + ')' : '')
                             : 'stock surface (no move)';
    readout.textContent = 'deviation ' + (d >= 0 ? '+' : '') + d.toPrecision(6) + ' ' + D.unit + ' (' + kind(d) +
        ') at (' + at.map(function (x) { return x.toFixed(4); }).join(', ') + '); ' + made;
    readout.setAttribute('data-deviation', d);
    readout.setAttribute('data-move', moves[t]);
    readout.setAttribute('data-line', lines[t]);
    readout.setAttribute('data-at', at.join(','));
    marker.position.copy(p); marker.visible = true; draw();
    return d;
  }
  var down = null;
  renderer.domElement.addEventListener('pointerdown', function (e) { down = [e.clientX, e.clientY]; });
  renderer.domElement.addEventListener('click', function (e) {
    // A drag that rotates the view is not a pick.
    if (down && Math.abs(e.clientX - down[0]) + Math.abs(e.clientY - down[1]) > 4) return;
    pick(e.clientX, e.clientY);
  });
  draw();
  section.setAttribute('data-view3d', 'ready ' + indices.length / 3 + ' triangles, ' + frames + ' frames');
  // report.html#click=X,Y,Z&from=DX,DY,DZ (part coordinates, `unit`): look at the whole part from
  // direction DX,DY,DZ, project the point X,Y,Z to the canvas with that camera and click there, as a
  // person would; the browser test reads the result. data-click also records the colour drawn at
  // that pixel before the click (the marker then covers it).
  var ask = /^#click=([-+0-9.e]+),([-+0-9.e]+),([-+0-9.e]+)&from=([-+0-9.e]+),([-+0-9.e]+),([-+0-9.e]+)$/
                .exec(location.hash);
  if (ask) {
    var n = ask.slice(1).map(Number);
    var point = new THREE.Vector3(n[0] - D.center[0], n[1] - D.center[1], n[2] - D.center[2]);
    var from = new THREE.Vector3(n[3], n[4], n[5]).normalize();
    if (Math.abs(from.z) > 0.99) camera.up.set(0, 1, 0);
    controls.target.set(0, 0, 0);
    camera.position.copy(from).multiplyScalar(3.2 * radius);
    controls.update();
    draw();
    var ndc = point.clone().project(camera);
    var rect = renderer.domElement.getBoundingClientRect();
    var cx = rect.left + (ndc.x + 1) / 2 * rect.width, cy = rect.top + (1 - ndc.y) / 2 * rect.height;
    var gl = renderer.getContext(), pixel = new Uint8Array(4), scale = gl.drawingBufferWidth / rect.width;
    gl.readPixels(Math.floor((cx - rect.left) * scale), Math.floor(gl.drawingBufferHeight - (cy - rect.top) * scale),
                  1, 1, gl.RGBA, gl.UNSIGNED_BYTE, pixel);
    renderer.domElement.dispatchEvent(new MouseEvent('pointerdown', {clientX: cx, clientY: cy, bubbles: true}));
    renderer.domElement.dispatchEvent(new MouseEvent('click', {clientX: cx, clientY: cy, bubbles: true}));
    section.setAttribute('data-click', 'deviation ' + readout.getAttribute('data-deviation') + ' move ' +
                         readout.getAttribute('data-move') + ' line ' + readout.getAttribute('data-line') +
                         ' at ' + readout.getAttribute('data-at') + ' pixel ' + pixel[0] + ',' + pixel[1] + ',' +
                         pixel[2]);
  }
})();
)JS";

std::string legend_html(const View3d& view) {
  std::string stops;
  for (int i = 0; i <= 10; ++i) {
    const morph::Color c = raytest::map_color(raytest::ColorMap::CoolWarm, i / 10.0);
    stops += fmt::format("{}rgb({},{},{}) {}%", i ? "," : "", c[0], c[1], c[2], i * 10);
  }
  return fmt::format(
      "<div class=\"view3d-legend\"><span>{:+.4g} {} (gouge)</span>"
      "<span style=\"display:inline-block;width:320px;height:14px;margin:0 8px;vertical-align:middle;"
      "background:linear-gradient(to right,{})\"></span><span>{:+.4g} {} (excess)</span>"
      " &nbsp; white centre = 0</div>\n",
      view.range.low, html_escape(view.unit), stops, view.range.high, html_escape(view.unit));
}

}  // namespace

std::string default_three_dir() {
  return MORPHMILL_THREE_JS_DIR;
}

std::string view3d_html(const View3d& view, const std::string& three_dir) {
  const morph::TriangleMesh& mesh = view.mesh;
  if (view.values.size() != mesh.vertices.size())
    throw std::invalid_argument("3D view: one deviation per vertex expected");
  if (!mesh.tags.empty() && mesh.tags.size() != mesh.triangles.size())
    throw std::invalid_argument("3D view: one tag per triangle expected");
  namespace fs = std::filesystem;
  const fs::path three = fs::path(three_dir) / "three.min.js";
  const fs::path orbit = fs::path(three_dir) / "examples" / "js" / "controls" / "OrbitControls.js";
  std::string out =
      "<section id=\"view3d\" data-view3d=\"loading\">\n<h3>3D view: " + html_escape(view.title) +
      "</h3>\n<p>Drag to rotate, wheel to zoom, right-drag to pan; click the part to read the "
      "deviation there and the move that made it.</p>\n" +
      (view.decimated
           ? fmt::format("<p class=\"view3d-decimated\">Shown decimated: {} of the {} triangles measured "
                         "(the tables and pictures use them all; values are measured at the shown "
                         "vertices).</p>\n",
                         mesh.triangles.size(), view.source_triangles)
           : std::string()) +
      legend_html(view) +
      "<div id=\"view3d-canvas\" style=\"width:100%;max-width:1000px;height:640px;"
      "border:1px solid #bbb\"></div>\n<p id=\"view3d-readout\">Click the part.</p>\n";
  std::error_code error;
  if (!fs::is_regular_file(three, error) || !fs::is_regular_file(orbit, error)) {
    return out + "<p>3D view unavailable: three.js not found in " + html_escape(three_dir) +
           " (Debian: libjs-three).</p>\n<script>document.getElementById('view3d').setAttribute("
           "'data-view3d','failed: three.js missing');</script>\n</section>\n";
  }

  const Eigen::Vector3d center = morph::bounds(mesh).center();
  std::vector<float> positions;
  positions.reserve(3 * mesh.vertices.size());
  for (const Eigen::Vector3d& v : mesh.vertices)
    for (int k = 0; k < 3; ++k) positions.push_back(static_cast<float>(v[k] - center[k]));
  std::vector<std::uint32_t> indices;
  indices.reserve(3 * mesh.triangles.size());
  for (const morph::Triangle& t : mesh.triangles) indices.insert(indices.end(), {t[0], t[1], t[2]});
  std::vector<std::uint8_t> colours;
  colours.reserve(3 * mesh.vertices.size());
  for (double d : view.values) {
    const morph::Color c = raytest::map_value(raytest::ColorMap::CoolWarm, view.range, d);
    colours.insert(colours.end(), {c[0], c[1], c[2]});
  }
  std::vector<std::int32_t> moves(mesh.triangles.size(), -1), lines(mesh.triangles.size(), 0);
  for (std::size_t t = 0; t < mesh.tags.size(); ++t) {
    moves[t] = mesh.tags[t].source;
    lines[t] = mesh.tags[t].line;
  }
  nlohmann::json data = {{"unit", view.unit},
                         {"band", {view.band_low, view.band_high}},
                         {"center", {center.x(), center.y(), center.z()}},
                         {"positions", base64_of(positions)},
                         {"indices", base64_of(indices)},
                         {"colours", base64_of(colours)},
                         {"values", base64_of(view.values)},
                         {"moves", base64_of(moves)},
                         {"lines", base64_of(lines)}};
  out += "<script type=\"application/json\" id=\"view3d-data\">" + script_safe(data.dump()) + "</script>\n";
  out += "<script>" + script_safe(read_file_bytes(three)) + "</script>\n";
  out += "<script>" + script_safe(read_file_bytes(orbit)) + "</script>\n";
  out += std::string("<script>") + kViewerScript + "</script>\n</section>\n";
  return out;
}

}  // namespace morphmill
