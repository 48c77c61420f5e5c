// rigsim teaching report: decoding the data files and the geometry the page computes with (poses,
// the camera models, epipolar curves, the true correspondence from depth), kept apart from the
// page so that the self-test checks the same functions the views draw with.
// Conventions are rigsim's: camera frame x right, y down, z forward; pixel (0, 0) is the centre of
// the top-left pixel; poses are target_from_source {rotation_wxyz, translation}.
'use strict';

var RIGSIM_GEOMETRY = (function () {
  // ---------------------------------------------------------------- decoding
  function bytes(b64) {
    var s = atob(b64), out = new Uint8Array(s.length);
    for (var i = 0; i < s.length; ++i) out[i] = s.charCodeAt(i);
    return out;
  }
  function floats(b64) { return new Float32Array(bytes(b64).buffer); }
  function uint16s(b64) { return new Uint16Array(bytes(b64).buffer); }
  var kRangeMin = 0.01, kRangeMax = 1.0e5;  // report_images.h QuantiseRanges
  function dequantise(q) {
    if (q === 0) return 0;
    var l0 = Math.log(kRangeMin), span = Math.log(kRangeMax) - l0;
    return Math.exp(l0 + (q - 1) / 65534 * span);
  }

  // ---------------------------------------------------------------- geometry
  function quatRotate(wxyz, v) {
    var w = wxyz[0], x = wxyz[1], y = wxyz[2], z = wxyz[3];
    // t = 2 q_vec x v; v' = v + w t + q_vec x t
    var tx = 2 * (y * v[2] - z * v[1]), ty = 2 * (z * v[0] - x * v[2]), tz = 2 * (x * v[1] - y * v[0]);
    return [v[0] + w * tx + (y * tz - z * ty), v[1] + w * ty + (z * tx - x * tz), v[2] + w * tz + (x * ty - y * tx)];
  }
  function quatMul(a, b) {
    return [a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
            a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
            a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
            a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0]];
  }
  function pose(p) { return {q: p.rotation_wxyz, t: p.translation}; }
  function apply(p, v) { var r = quatRotate(p.q, v); return [r[0] + p.t[0], r[1] + p.t[1], r[2] + p.t[2]]; }
  function inverse(p) {
    var qi = [p.q[0], -p.q[1], -p.q[2], -p.q[3]];
    var t = quatRotate(qi, p.t);
    return {q: qi, t: [-t[0], -t[1], -t[2]]};
  }
  function compose(a, b) {  // a * b
    return {q: quatMul(a.q, b.q), t: apply(a, b.t)};
  }
  function centre(camFromWorld) { return inverse(camFromWorld).t; }

  // Camera models (geometry/camera_models.h), the same algebra as the C++.
  function distort(cam, u, v) {
    var p = cam.params, m = cam.model;
    if (m === 'PINHOLE') return [u, v];
    var u2 = u * u, v2 = v * v, uv = u * v, r2 = u2 + v2, radial;
    var k1 = p[4], k2 = p[5], p1 = p[6], p2 = p[7];
    if (m === 'OPENCV') {
      radial = 1 + r2 * (k1 + k2 * r2);
    } else {  // FULL_OPENCV
      var r4 = r2 * r2, r6 = r4 * r2;
      radial = (1 + k1 * r2 + k2 * r4 + p[8] * r6) / (1 + p[9] * r2 + p[10] * r4 + p[11] * r6);
    }
    return [u * radial + 2 * p1 * uv + p2 * (r2 + 2 * u2), v * radial + p1 * (r2 + 2 * v2) + 2 * p2 * uv];
  }
  function fisheyeTheta(cam, theta) {
    var p = cam.params, t2 = theta * theta;
    return theta * (1 + t2 * (p[4] + t2 * (p[5] + t2 * (p[6] + t2 * p[7]))));
  }
  // Pixel of a point in the camera frame, or null outside the lens's valid field of view.
  function imgFromCam(cam, x) {
    var p = cam.params, ud, vd;
    if (cam.model === 'OPENCV_FISHEYE') {
      var r = Math.hypot(x[0], x[1]);
      var theta = Math.atan2(r, x[2]);
      if (theta > cam.max_angle_rad) return null;
      if (r === 0) { ud = 0; vd = 0; } else {
        var s = fisheyeTheta(cam, theta) / r;
        ud = x[0] * s; vd = x[1] * s;
      }
    } else {
      if (!(x[2] > 0)) return null;
      if (Math.hypot(x[0], x[1]) > Math.tan(cam.max_angle_rad) * x[2]) return null;
      var d = distort(cam, x[0] / x[2], x[1] / x[2]);
      ud = d[0]; vd = d[1];
    }
    return [p[0] * ud + p[2], p[1] * vd + p[3]];
  }
  // Unit ray (camera frame) of a pixel, or null where the lens has none.
  function camFromImg(cam, px) {
    var p = cam.params;
    var du = (px[0] - p[2]) / p[0], dv = (px[1] - p[3]) / p[1];
    if (cam.model === 'OPENCV_FISHEYE') {
      var td = Math.hypot(du, dv);
      if (td === 0) return [0, 0, 1];
      var maxT = cam.max_angle_rad;
      if (td > fisheyeTheta(cam, maxT)) return null;
      var lo = 0, hi = maxT, th = Math.min(td, maxT);
      for (var i = 0; i < 200; ++i) {  // bisection safeguarded Newton
        var f = fisheyeTheta(cam, th) - td;
        if (f === 0) break;
        if (f > 0) hi = th; else lo = th;
        var h = 1e-7 * Math.max(1, th);
        var dfd = (fisheyeTheta(cam, th + h) - fisheyeTheta(cam, th - h)) / (2 * h);
        var next = dfd > 0 ? th - f / dfd : 0.5 * (lo + hi);
        if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
        if (Math.abs(next - th) <= 1e-16 * Math.max(1, th)) { th = next; break; }
        th = next;
      }
      var s = Math.sin(th) / td;
      return [du * s, dv * s, Math.cos(th)];
    }
    var x = [du, dv];
    if (cam.model !== 'PINHOLE') {
      x = newtonUndistort(cam, [du, dv], [du, dv]);
      if (!x) {  // near the lens's fold Newton can leave the valid branch: start from inside
        x = newtonUndistort(cam, [du, dv], [du * 0.5, dv * 0.5]);
      }
      if (!x || Math.hypot(x[0], x[1]) > Math.tan(cam.max_angle_rad) * (1 + 1e-9)) return null;
    }
    var n = Math.hypot(x[0], x[1], 1);
    return [x[0] / n, x[1] / n, 1 / n];
  }
  function newtonUndistort(cam, target, x) {
    x = x.slice();
    for (var it = 0; it < 50; ++it) {
      var d = distort(cam, x[0], x[1]);
      var fu = d[0] - target[0], fv = d[1] - target[1];
      var h = 1e-7 * Math.max(1, Math.hypot(x[0], x[1]));
      var du1 = distort(cam, x[0] + h, x[1]), du0 = distort(cam, x[0] - h, x[1]);
      var dv1 = distort(cam, x[0], x[1] + h), dv0 = distort(cam, x[0], x[1] - h);
      var a = (du1[0] - du0[0]) / (2 * h), b = (dv1[0] - dv0[0]) / (2 * h);
      var c = (du1[1] - du0[1]) / (2 * h), e = (dv1[1] - dv0[1]) / (2 * h);
      var det = a * e - b * c;
      if (!(Math.abs(det) > 1e-300)) return null;
      var su = (e * fu - b * fv) / det, sv = (-c * fu + a * fv) / det;
      x[0] -= su; x[1] -= sv;
      if (Math.hypot(su, sv) <= 1e-15 * Math.max(1, Math.hypot(x[0], x[1]))) break;
    }
    var dd = distort(cam, x[0], x[1]);
    var err = Math.hypot((dd[0] - target[0]) * cam.params[0], (dd[1] - target[1]) * cam.params[1]);
    return err < 1e-6 ? x : null;
  }
  // The epipolar curve of pixel pxA (report_geometry.h EpipolarCurve): B's pixel of the point at
  // each depth along A's ray, then of the point at infinity; null where B does not image it.
  function epipolarCurve(camA, pxA, camB, bFromA, depths) {
    var ray = camFromImg(camA, pxA);
    if (!ray) return [];
    var out = depths.map(function (d) { return imgFromCam(camB, apply(bFromA, [ray[0] * d, ray[1] * d, ray[2] * d])); });
    out.push(imgFromCam(camB, quatRotate(bFromA.q, ray)));
    return out;
  }
  function logDepths(near, far, count) {
    var d = [];
    for (var i = 0; i < count; ++i) d.push(near * Math.pow(far / near, i / (count - 1)));
    return d;
  }
  // Range (m) of a view's quantised grid at full-resolution pixel px (nearest grid cell).
  function rangeAt(depth, cam, px) {
    if (!depth) return 0;
    var gx = Math.floor((px[0] + 0.5) * depth.width / cam.width), gy = Math.floor((px[1] + 0.5) * depth.height / cam.height);
    if (gx < 0 || gy < 0 || gx >= depth.width || gy >= depth.height) return 0;
    return dequantise(depth.values[gy * depth.width + gx]);
  }
  // dataset/ground_truth.h TransferPixel: A's pixel lifted with its true range, projected into B,
  // visible when B's range there agrees (2% or 5 cm).
  function transfer(camA, depthA, pxA, camB, depthB, bFromA) {
    var r = rangeAt(depthA, camA, pxA);
    var ray = camFromImg(camA, pxA);
    if (!(r > 0) || !ray) return {point: null, why: 'no surface at this pixel (sky or background): no true depth'};
    var x = apply(bFromA, [ray[0] * r, ray[1] * r, ray[2] * r]);
    var px = imgFromCam(camB, x);
    if (!px) return {point: null, why: 'the point is outside the other camera\'s field of view'};
    if (px[0] < -0.5 || px[1] < -0.5 || px[0] >= camB.width - 0.5 || px[1] >= camB.height - 0.5) {
      return {point: null, projected: px, why: 'the point projects outside the other image'};
    }
    var dist = Math.hypot(x[0], x[1], x[2]);
    var rb = rangeAt(depthB, camB, px);
    if (!(rb > 0) || Math.abs(rb - dist) > Math.max(0.05, 0.02 * dist)) {
      return {point: null, projected: px, why: 'the point is hidden in the other view (occluded)'};
    }
    return {point: px, why: ''};
  }

  return {bytes: bytes, floats: floats, uint16s: uint16s, dequantise: dequantise, quatRotate: quatRotate, quatMul: quatMul, pose: pose, apply: apply, inverse: inverse, compose: compose, centre: centre, distort: distort, fisheyeTheta: fisheyeTheta, imgFromCam: imgFromCam, camFromImg: camFromImg, newtonUndistort: newtonUndistort, epipolarCurve: epipolarCurve, logDepths: logDepths, rangeAt: rangeAt, transfer: transfer};
})();
