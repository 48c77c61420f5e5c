// rigsim teaching report: the page. Data come from data/*.js files (RIGSIM.put), loaded with
// <script src>, which a page opened from disk may do (it may not fetch() its own files).
// Conventions are rigsim's: camera frame x right, y down, z forward; pixel (0, 0) is the centre of
// the top-left pixel; poses are target_from_source {rotation_wxyz, translation}; world = glTF's.
'use strict';

var RIGSIM = (function () {
  var store = {};
  var loading = {};
  var R = null;  // the report's data

  function put(key, value) { store[key] = value; }

  // Loads a data script once; resolves with what it put under `key`.
  function load(src, key) {
    if (store[key] !== undefined) return Promise.resolve(store[key]);
    if (!loading[src]) {
      loading[src] = new Promise(function (resolve, reject) {
        var s = document.createElement('script');
        s.src = src;
        s.onload = function () { resolve(); };
        s.onerror = function () { reject(new Error('cannot load ' + src)); };
        document.head.appendChild(s);
      });
    }
    return loading[src].then(function () {
      if (store[key] === undefined) throw new Error(src + ' did not define ' + key);
      return store[key];
    });
  }

  // Decoding and geometry (geometry.js): what the page uses of it.
  var G = RIGSIM_GEOMETRY;
  var bytes = G.bytes, floats = G.floats, uint16s = G.uint16s, quatRotate = G.quatRotate, pose = G.pose,
      inverse = G.inverse, compose = G.compose, centre = G.centre, imgFromCam = G.imgFromCam,
      camFromImg = G.camFromImg, epipolarCurve = G.epipolarCurve, logDepths = G.logDepths,
      transfer = G.transfer;

  // ---------------------------------------------------------------- page helpers
  function $(id) { return document.getElementById(id); }
  function el(tag, attrs, text) {
    var e = document.createElement(tag);
    for (var k in attrs || {}) e.setAttribute(k, attrs[k]);
    if (text !== undefined) e.textContent = text;
    return e;
  }
  function options(select, items, selected) {
    select.innerHTML = '';
    items.forEach(function (it, i) {
      var o = el('option', {value: String(it.value !== undefined ? it.value : i)}, it.label !== undefined ? it.label : String(it));
      select.appendChild(o);
    });
    if (selected !== undefined) select.value = String(selected);
  }
  function fmt(v, digits, unit) {
    if (v === null || v === undefined || (typeof v === 'number' && !isFinite(v))) return '-';
    return v.toFixed(digits) + (unit || '');
  }
  function pct(a, b) { return b > 0 ? (100 * a / b).toFixed(1) + '%' : '-'; }
  function table(headers, rows) {
    var t = el('table'), tr = el('tr');
    headers.forEach(function (h, i) { tr.appendChild(el('th', {class: i === 0 ? 'text' : ''}, h)); });
    t.appendChild(tr);
    rows.forEach(function (r) {
      var row = el('tr');
      r.forEach(function (c, i) {
        var td = el('td', {class: i === 0 || c instanceof Node || (typeof c === 'string' && c.length > 14) ? 'text' : ''});
        if (c instanceof Node) td.appendChild(c); else td.textContent = c;
        row.appendChild(td);
      });
      t.appendChild(row);
    });
    return t;
  }
  function loadImage(src) {
    return new Promise(function (resolve, reject) {
      var img = new Image();
      img.onload = function () { resolve(img); };
      img.onerror = function () { reject(new Error('cannot load ' + src)); };
      img.src = src;
    });
  }
  var modeColours = {'none': '#ff9a3c', 'mask': '#3cd0ff', 'gated': '#e36bff', 'mask+gated': '#ffe14d'};
  function modeColour(name) { return modeColours[name] || '#ff9a3c'; }
  function camName(c) { return R.cameras[c].name; }
  function classById(id) { return R.class_legend[id]; }
  function rgb(c) { return 'rgb(' + c[0] + ',' + c[1] + ',' + c[2] + ')'; }

  // ---------------------------------------------------------------- tabs
  var tabs = {};
  function showTab(name) {
    if (!tabs[name]) name = 'scene';
    document.querySelectorAll('.tab').forEach(function (s) { s.classList.toggle('active', s.id === 'tab-' + name); });
    document.querySelectorAll('#tabs a').forEach(function (a) { a.classList.toggle('active', a.dataset.tab === name); });
    if (tabs[name].shown) tabs[name].shown();
  }

  // ---------------------------------------------------------------- 1. the scene in 3D
  var scene3d = {ready: null};
  function setupScene() {
    var S = R.scene;
    var container = $('scene-view');
    options($('scene-mode'), R.modes.map(function (m, i) { return {value: i, label: m}; }), 0);
    options($('scene-frame'), [{value: -1, label: 'all'}].concat(R.frames.map(function (f, i) { return {value: i, label: f}; })), -1);
    var legend = $('scene-legend');
    legend.innerHTML = '';
    [['#ffffff', 'true camera (frustum: its field of view through its lens)'],
     ['#ffd000', 'true trajectory of camera 0']].forEach(function (l) {
      var d = el('div'); d.appendChild(el('span', {class: 'swatch', style: 'background:' + l[0]})); d.appendChild(document.createTextNode(l[1])); legend.appendChild(d);
    });
    R.modes.forEach(function (m) {
      var d = el('div'); d.appendChild(el('span', {class: 'swatch', style: 'background:' + modeColour(m)}));
      d.appendChild(document.createTextNode('estimate, ' + m + ' (dashed: rotation only, at the true centre)')); legend.appendChild(d);
    });

    var renderer = new THREE.WebGLRenderer({antialias: true, preserveDrawingBuffer: true});
    renderer.setPixelRatio(window.devicePixelRatio || 1);
    renderer.gammaOutput = true;
    renderer.gammaFactor = 2.2;
    renderer.setClearColor(0x15171b);
    container.insertBefore(renderer.domElement, container.firstChild);
    var world = new THREE.Scene();
    world.add(new THREE.HemisphereLight(0xffffff, 0x445566, 0.9));
    var sun = new THREE.DirectionalLight(0xffffff, 0.7);
    sun.position.set(30, 60, 20);
    world.add(sun);
    var camera = new THREE.PerspectiveCamera(55, 1, 0.05, 5000);
    var controls = new THREE.OrbitControls(camera, renderer.domElement);
    var groups = {scene: new THREE.Group(), truth: new THREE.Group(), estimate: new THREE.Group(),
                  points: new THREE.Group(), trajectory: new THREE.Group()};
    Object.keys(groups).forEach(function (k) { world.add(groups[k]); });
    var pickables = [];

    function render() {
      var w = container.clientWidth, h = container.clientHeight;
      if (w === 0 || h === 0) return;
      if (renderer.domElement.width !== Math.floor(w * renderer.getPixelRatio())) {
        renderer.setSize(w, h);
        camera.aspect = w / h;
        camera.updateProjectionMatrix();
      }
      renderer.render(world, camera);
      scene3d.rendered = (scene3d.rendered || 0) + 1;
    }
    controls.addEventListener('change', render);
    window.addEventListener('resize', render);

    // world_from_cam as a THREE matrix (rigsim's camera axes: x right, y down, z forward).
    function worldFromCamMatrix(camFromWorld) {
      var inv = inverse(camFromWorld);
      var m = new THREE.Matrix4();
      var q = new THREE.Quaternion(inv.q[1], inv.q[2], inv.q[3], inv.q[0]);
      m.compose(new THREE.Vector3(inv.t[0], inv.t[1], inv.t[2]), q, new THREE.Vector3(1, 1, 1));
      return m;
    }
    function frustum(c, colour, dashed, size) {
      var outline = S.cameras[c].fov_outline;
      var pts = [];
      var step = Math.max(1, Math.floor(outline.length / 8));
      for (var i = 0; i < outline.length; ++i) {
        var a = outline[i], b = outline[(i + 1) % outline.length];
        pts.push(a[0] * size, a[1] * size, a[2] * size, b[0] * size, b[1] * size, b[2] * size);
        if (i % step === 0) pts.push(0, 0, 0, a[0] * size, a[1] * size, a[2] * size);
      }
      // The image's top edge marked: which way is up in the photo.
      pts.push(0, 0, 0, 0, -0.35 * size, 0);
      var g = new THREE.BufferGeometry();
      g.setAttribute('position', new THREE.Float32BufferAttribute(pts, 3));
      var mat = dashed ? new THREE.LineDashedMaterial({color: colour, dashSize: size * 0.08, gapSize: size * 0.06})
                       : new THREE.LineBasicMaterial({color: colour});
      var lines = new THREE.LineSegments(g, mat);
      if (dashed) lines.computeLineDistances();
      return lines;
    }
    function frameList() {
      var f = Number($('scene-frame').value);
      return f < 0 ? R.frames.map(function (_, i) { return i; }) : [f];
    }
    var size = $('frustum-size');
    function rebuild() {
      ['truth', 'estimate', 'points', 'trajectory'].forEach(function (k) {
        var g = groups[k];
        while (g.children.length) g.remove(g.children[0]);
      });
      pickables = [];
      var s = Number(size.value);
      var frames = frameList();
      var mode = Number($('scene-mode').value);
      var M = S.modes[mode];
      if (S.truth_cam_from_world) {
        frames.forEach(function (f) {
          S.truth_cam_from_world[f].forEach(function (p, c) {
            var obj = frustum(c, 0xffffff, false, s);
            obj.matrixAutoUpdate = false;
            obj.matrix.copy(worldFromCamMatrix(pose(p)));
            groups.truth.add(obj);
            var ball = new THREE.Mesh(new THREE.SphereGeometry(s * 0.05, 12, 8), new THREE.MeshBasicMaterial({color: 0xffffff}));
            var cc = centre(pose(p));
            ball.position.set(cc[0], cc[1], cc[2]);
            ball.userData = {camera: c, frame: f};
            groups.truth.add(ball);
            pickables.push(ball);
          });
          // The estimate in the truth's world: cam_from_world = cam_from_cam0 * true cam0_from_world.
          var cam0 = pose(S.truth_cam_from_world[f][0]);
          M.cameras.forEach(function (e, c) {
            if (!e) return;
            var est = compose(pose(e.cam_from_cam0), cam0);
            var obj = frustum(c, modeColour(M.name), e.rotation_only, s);
            obj.matrixAutoUpdate = false;
            obj.matrix.copy(worldFromCamMatrix(est));
            groups.estimate.add(obj);
          });
        });
        var traj = S.truth_trajectory;
        groups.trajectory.add(polyline(traj, 0xffd000));
      } else {
        M.cameras.forEach(function (e, c) {
          if (!e) return;
          var obj = frustum(c, modeColour(M.name), e.rotation_only, s);
          obj.matrixAutoUpdate = false;
          obj.matrix.copy(worldFromCamMatrix(pose(e.cam_from_cam0)));
          groups.estimate.add(obj);
        });
      }
      var est = M.trajectory.filter(function (p) { return p; });
      if (est.length > 1) groups.trajectory.add(polyline(est, new THREE.Color(modeColour(M.name)).getHex()));
      var xyz = floats(M.points);
      if (xyz.length) {
        var g = new THREE.BufferGeometry();
        g.setAttribute('position', new THREE.BufferAttribute(xyz, 3));
        groups.points.add(new THREE.Points(g, new THREE.PointsMaterial({color: modeColour(M.name), size: 2, sizeAttenuation: false})));
      }
      visibility();
    }
    function polyline(points, colour) {
      var g = new THREE.BufferGeometry();
      var flat = [];
      points.forEach(function (p) { flat.push(p[0], p[1], p[2]); });
      g.setAttribute('position', new THREE.Float32BufferAttribute(flat, 3));
      return new THREE.Line(g, new THREE.LineBasicMaterial({color: colour}));
    }
    function visibility() {
      groups.scene.visible = $('show-scene').checked;
      groups.truth.visible = $('show-truth').checked;
      groups.estimate.visible = $('show-estimate').checked;
      groups.points.visible = $('show-points').checked;
      groups.trajectory.visible = $('show-trajectory').checked;
      render();
    }
    ['show-scene', 'show-truth', 'show-estimate', 'show-points', 'show-trajectory'].forEach(function (id) {
      $(id).addEventListener('change', visibility);
    });
    ['scene-mode', 'scene-frame'].forEach(function (id) { $(id).addEventListener('change', rebuild); });
    size.addEventListener('input', rebuild);

    // Where to look from: the true camera centres (or the estimate's), from behind and above.
    var centres = [];
    if (S.truth_cam_from_world) {
      S.truth_cam_from_world.forEach(function (f) { f.forEach(function (p) { centres.push(centre(pose(p))); }); });
    } else {
      centres.push([0, 0, 0]);
    }
    var mid = [0, 0, 0];
    centres.forEach(function (c) { mid[0] += c[0] / centres.length; mid[1] += c[1] / centres.length; mid[2] += c[2] / centres.length; });
    var extent = 0;
    centres.forEach(function (c) { extent = Math.max(extent, Math.hypot(c[0] - mid[0], c[1] - mid[1], c[2] - mid[2])); });
    var frame0 = S.truth_cam_from_world ? S.truth_cam_from_world[0] : null;
    var rigExtent = 0;
    if (frame0) {
      var c0 = centre(pose(frame0[0]));
      frame0.forEach(function (p) { var c = centre(pose(p)); rigExtent = Math.max(rigExtent, Math.hypot(c[0] - c0[0], c[1] - c0[1], c[2] - c0[2])); });
    }
    size.value = String(Math.min(2, Math.max(0.3, 0.9 * (rigExtent || 1))));
    // From behind camera 0 and above, looking down the rig's way.
    var forward = frame0 ? quatRotate(inverse(pose(frame0[0])).q, [0, 0, 1]) : [0, 0, 1];
    var dist = Math.max(3, 1.2 * extent + 3 * (rigExtent || 1));
    camera.position.set(mid[0] - forward[0] * dist, mid[1] + 0.8 * dist, mid[2] - forward[2] * dist);
    controls.target.set(mid[0] + forward[0] * 0.5 * dist, mid[1] - 0.5, mid[2] + forward[2] * 0.5 * dist);
    controls.update();

    // Click (without dragging) on a camera's ball: its views.
    var down = null;
    renderer.domElement.addEventListener('pointerdown', function (e) { down = [e.clientX, e.clientY]; });
    renderer.domElement.addEventListener('pointerup', function (e) {
      if (!down || Math.hypot(e.clientX - down[0], e.clientY - down[1]) > 4) return;
      var rect = renderer.domElement.getBoundingClientRect();
      var ndc = new THREE.Vector2((e.clientX - rect.left) / rect.width * 2 - 1, -(e.clientY - rect.top) / rect.height * 2 + 1);
      var ray = new THREE.Raycaster();
      ray.setFromCamera(ndc, camera);
      var hits = ray.intersectObjects(pickables);
      if (hits.length) openView(hits[0].object.userData.camera, hits[0].object.userData.frame);
    });

    var list = $('scene-cameras');
    list.innerHTML = '';
    R.cameras.forEach(function (c, i) {
      var a = el('div', {class: 'camera-link'}, c.name + ' (' + c.model + ', ' + c.width + 'x' + c.height + ')');
      a.addEventListener('click', function () { openView(i, 0); });
      list.appendChild(a);
    });

    rebuild();
    scene3d.render = render;
    scene3d.renderer = renderer;
    var note = $('scene-note');
    if (S.glb) {
      note.textContent = 'loading the scene ' + (S.scene_name || '') + '...';
      scene3d.ready = load(S.glb, 'scene').then(function (b64) {
        return new Promise(function (resolve, reject) {
          new THREE.GLTFLoader().parse(bytes(b64).buffer, '', function (gltf) {
            groups.scene.add(gltf.scene);
            note.textContent = 'scene: ' + (S.scene_name || '') + ' (glTF, in its own coordinates = rigsim\'s world)';
            render();
            resolve();
          }, function (err) { reject(err); });
        });
      }).catch(function (err) { note.textContent = 'the scene could not be shown: ' + err; console.error(err); });
    } else {
      note.textContent = 'no scene embedded (' + (S.scene_name || 'unknown') + ' was not found when the report was written)';
      scene3d.ready = Promise.resolve();
    }
  }
  tabs.scene = {shown: function () { if (scene3d.render) scene3d.render(); }};

  // ---------------------------------------------------------------- 2. camera views
  var viewState = {camera: 0, frame: 0};
  function openView(c, f) {
    $('view-camera').value = String(c);
    $('view-frame').value = String(f);
    location.hash = 'views';
    drawView();
  }
  function setupViews() {
    options($('view-camera'), R.cameras.map(function (c, i) { return {value: i, label: c.name}; }), 0);
    options($('view-frame'), R.frames.map(function (f, i) { return {value: i, label: f}; }), 0);
    options($('view-mode'), R.modes.map(function (m) { return {value: m, label: m}; }), R.modes[0]);
    ['view-camera', 'view-frame', 'view-base', 'view-mode', 'view-keypoints'].forEach(function (id) {
      $(id).addEventListener('change', drawView);
    });
    $('view-labels').addEventListener('input', drawView);
  }
  function viewData(c, f) { return load(R.views[c][f].data, 'view/' + c + '/' + f); }
  var drawSerial = 0;
  function drawView() {
    var c = Number($('view-camera').value), f = Number($('view-frame').value);
    var v = R.views[c][f];
    var serial = ++drawSerial;
    var base = $('view-base').value;
    var baseSrc = v[base] || v.rgb;
    var opacity = Number($('view-labels').value);
    var jobs = [loadImage(baseSrc), v.labels ? loadImage(v.labels) : Promise.resolve(null), viewData(c, f)];
    return Promise.all(jobs).then(function (got) {
      if (serial !== drawSerial) return;
      var canvas = $('view-canvas');
      canvas.width = v.width; canvas.height = v.height;
      var ctx = canvas.getContext('2d');
      var u = Math.max(1, v.width / 1000);  // marks in screen pixels
      ctx.drawImage(got[0], 0, 0, v.width, v.height);
      if (got[1] && opacity > 0) { ctx.globalAlpha = opacity; ctx.drawImage(got[1], 0, 0, v.width, v.height); ctx.globalAlpha = 1; }
      var data = got[2], mode = $('view-mode').value;
      var kp = data.keypoints[mode];
      var legend = $('view-keypoint-legend');
      legend.innerHTML = '';
      if ($('view-keypoints').checked && kp) {
        var xy = floats(kp.xy), inMask = kp.in_mask ? bytes(kp.in_mask) : null;
        var usesMask = mode.indexOf('mask') >= 0;
        var kept = 0;
        for (var i = 0; i < kp.count; ++i) {
          var keep = usesMask || !inMask || inMask[i];
          kept += keep ? 1 : 0;
          ctx.fillStyle = keep ? '#39ff6a' : '#ff3b3b';
          ctx.fillRect((xy[2 * i] + 0.5) * data.scale - 1.5 * u, (xy[2 * i + 1] + 0.5) * data.scale - 1.5 * u, 3 * u, 3 * u);
        }
        var lines = usesMask
            ? [['#39ff6a', kp.count + ' keypoints detected inside the reliable-class mask (' + mode + ')']]
            : [['#39ff6a', kept + ' of ' + kp.count + ' on reliable classes: the mask would keep them'],
               ['#ff3b3b', (kp.count - kept) + ' the mask drops (sky, vegetation, vehicles, people, class borders)']];
        if (!usesMask && !inMask) lines = [['#39ff6a', kp.count + ' keypoints (no labels to tell which the mask keeps)']];
        lines.forEach(function (l) {
          var d = el('div'); d.appendChild(el('span', {class: 'swatch', style: 'background:' + l[0]}));
          d.appendChild(document.createTextNode(l[1])); legend.appendChild(d);
        });
      }
      var cl = $('view-legend');
      cl.innerHTML = '';
      v.classes.slice().sort(function (a, b) { return b[1] - a[1]; }).forEach(function (e) {
        var k = classById(e[0]);
        if (!k) return;
        var d = el('div'); d.appendChild(el('span', {class: 'swatch', style: 'background:' + rgb(k.color)}));
        d.appendChild(document.createTextNode(k.name + ' ' + (100 * e[1]).toFixed(1) + '%' + (k.reliable ? ' (reliable)' : '')));
        cl.appendChild(d);
      });
    });
  }
  tabs.views = {shown: function () { drawView(); }};

  // ---------------------------------------------------------------- 3. camera pairs
  var pairState = {click: null, last: null};
  var kInlier = 1, kChecked = 2, kCorrect = 4;  // report_pairs.cc
  var categories = [
    {key: 'in_right', label: 'inlier, right by the truth', colour: '#39ff6a', test: function (f) { return (f & kInlier) && (f & kChecked) && (f & kCorrect); }},
    {key: 'in_wrong', label: 'inlier, wrong by the truth', colour: '#ff2d2d', test: function (f) { return (f & kInlier) && (f & kChecked) && !(f & kCorrect); }},
    {key: 'out_right', label: 'outlier (rejected), right by the truth', colour: '#4aa3ff', test: function (f) { return !(f & kInlier) && (f & kChecked) && (f & kCorrect); }},
    {key: 'out_wrong', label: 'outlier (rejected), wrong by the truth', colour: '#b07cff', test: function (f) { return !(f & kInlier) && (f & kChecked) && !(f & kCorrect); }},
    {key: 'in_unknown', label: 'inlier, not checked (no depth)', colour: '#c8ffc8', test: function (f) { return (f & kInlier) && !(f & kChecked); }},
    {key: 'out_unknown', label: 'outlier, not checked (no depth)', colour: '#8a8a8a', test: function (f) { return !(f & kInlier) && !(f & kChecked); }}];
  function setupPairs() {
    var best = 0, bestInliers = -1;
    R.pairs.forEach(function (p, i) {
      var m = p.modes[R.modes[0]];
      if (m && m.inliers > bestInliers) { bestInliers = m.inliers; best = i; }
    });
    options($('pair-select'), R.pairs.map(function (p, i) {
      var m = p.modes[R.modes[0]];
      return {value: i, label: camName(p.a) + ' - ' + camName(p.b) + (p.overlap !== null ? ' (true overlap ' + (100 * p.overlap).toFixed(0) + '%)' : '') +
              (m && !m.success ? ' failed' : '')};
    }), best);
    options($('pair-frame'), R.frames.map(function (f, i) { return {value: i, label: f}; }), 0);
    options($('pair-mode'), R.modes.map(function (m) { return {value: m, label: m}; }), R.modes[0]);
    var box = $('pair-categories');
    box.innerHTML = '';
    categories.forEach(function (c) {
      var l = el('label');
      var cb = el('input', {type: 'checkbox', id: 'cat-' + c.key});
      cb.checked = c.key !== 'out_right' && c.key !== 'out_unknown';
      cb.addEventListener('change', drawPair);
      l.appendChild(cb);
      l.appendChild(el('span', {class: 'swatch', style: 'background:' + c.colour}));
      l.appendChild(el('span', {id: 'count-' + c.key}, c.label));
      box.appendChild(l);
    });
    ['pair-select', 'pair-frame', 'pair-mode'].forEach(function (id) {
      $(id).addEventListener('change', function () { pairState.click = null; drawPair(); });
    });
    ['pair-overlap', 'pair-lines'].forEach(function (id) { $(id).addEventListener('change', drawPair); });
    $('pair-canvas').addEventListener('click', function (e) {
      var lay = pairState.layout;
      if (!lay) return;
      var rect = this.getBoundingClientRect();
      var x = (e.clientX - rect.left) * this.width / rect.width, y = (e.clientY - rect.top) * this.height / rect.height;
      var side = x >= lay.offsetB ? 'b' : 'a';
      var s = side === 'a' ? lay.scaleA : lay.scaleB, ox = side === 'a' ? 0 : lay.offsetB;
      pairState.click = {side: side, px: [(x - ox) / s - 0.5, y / s - 0.5]};
      drawPair();
    });
  }
  // Everything the pair view shows for the current selection, loaded.
  function pairInputs() {
    var p = Number($('pair-select').value), f = Number($('pair-frame').value);
    var P = R.pairs[p];
    return Promise.all([load(P.data, 'pair/' + p), viewData(P.a, f), viewData(P.b, f),
                        loadImage(R.views[P.a][f].rgb), loadImage(R.views[P.b][f].rgb)]).then(function (got) {
      return {p: p, f: f, P: P, pair: got[0], va: got[1], vb: got[2], ia: got[3], ib: got[4]};
    });
  }
  function depthOf(v) {
    if (!v.depth) return null;
    if (!v.depth.values) v.depth.values = uint16s(v.depth.q);
    return v.depth;
  }
  // The curves and the true point of a click, computed from the data alone (also the self-test's).
  function clickGeometry(P, mode, click, va, vb) {
    var a = R.cameras[P.a], b = R.cameras[P.b];
    var from = click.side === 'a' ? a : b, to = click.side === 'a' ? b : a;
    var flip = function (p) { return click.side === 'a' ? p : inverse(p); };
    var depths = logDepths(0.05, 1e4, 400);
    var out = {truth: null, estimate: null, transfer: null};
    if (P.b_from_a_truth) out.truth = epipolarCurve(from, click.px, to, flip(pose(P.b_from_a_truth)), depths);
    var m = P.modes[mode];
    if (m && m.b_from_a_rig) out.estimate = epipolarCurve(from, click.px, to, flip(pose(m.b_from_a_rig)), depths);
    if (P.b_from_a_truth) {
      var da = depthOf(click.side === 'a' ? va : vb), db = depthOf(click.side === 'a' ? vb : va);
      if (da && db) out.transfer = transfer(from, da, click.px, to, db, flip(pose(P.b_from_a_truth)));
    }
    return out;
  }
  function drawPair() {
    return pairInputs().then(function (I) {
      var mode = $('pair-mode').value;
      var a = R.cameras[I.P.a], b = R.cameras[I.P.b];
      var wa = R.views[I.P.a][I.f].width, ha = R.views[I.P.a][I.f].height;
      var wb = R.views[I.P.b][I.f].width, hb = R.views[I.P.b][I.f].height;
      var gap = 8;
      var canvas = $('pair-canvas');
      canvas.width = wa + gap + wb; canvas.height = Math.max(ha, hb);
      var lay = {scaleA: wa / a.width, scaleB: wb / b.width, offsetB: wa + gap};
      pairState.layout = lay;
      var ctx = canvas.getContext('2d');
      // Marks, lines and text in screen pixels: the canvas is shown scaled to the page's width.
      var u = Math.max(1, canvas.width / 1300);
      ctx.fillStyle = '#000'; ctx.fillRect(0, 0, canvas.width, canvas.height);
      ctx.drawImage(I.ia, 0, 0, wa, ha);
      ctx.drawImage(I.ib, lay.offsetB, 0, wb, hb);
      var frame = I.pair.frames[I.f];
      if ($('pair-overlap').checked && frame.overlap) {
        shade(ctx, frame.overlap.a, 0, wa, ha);
        shade(ctx, frame.overlap.b, lay.offsetB, wb, hb);
      }
      ctx.font = 'bold ' + Math.round(15 * u) + 'px system-ui, sans-serif';
      ctx.fillStyle = '#fff';
      ctx.strokeStyle = '#000'; ctx.lineWidth = 3 * u;
      [[a.name, 6 * u], [b.name, lay.offsetB + 6 * u]].forEach(function (t) {
        ctx.strokeText(t[0], t[1], 20 * u); ctx.fillText(t[0], t[1], 20 * u);
      });
      var pa = function (x, y) { return [(x + 0.5) * lay.scaleA, (y + 0.5) * lay.scaleA]; };
      var pb = function (x, y) { return [lay.offsetB + (x + 0.5) * lay.scaleB, (y + 0.5) * lay.scaleB]; };
      var M = frame.modes[mode];
      var counts = {};
      categories.forEach(function (c) { counts[c.key] = 0; });
      if (M && M.count) {
        var xa = floats(M.a), xb = floats(M.b), flags = bytes(M.flags);
        var lines = $('pair-lines').checked;
        var shown = 0;
        for (var i = 0; i < M.count; ++i) {
          var cat = null;
          for (var k = 0; k < categories.length; ++k) { if (categories[k].test(flags[i])) { cat = categories[k]; break; } }
          counts[cat.key]++;
          if (!$('cat-' + cat.key).checked) continue;
          var qa = pa(xa[2 * i], xa[2 * i + 1]), qb = pb(xb[2 * i], xb[2 * i + 1]);
          ctx.strokeStyle = cat.colour; ctx.fillStyle = cat.colour;
          // Every match's two ends; a line for an even subset (all lines hide the images).
          ctx.fillRect(qa[0] - 1.5 * u, qa[1] - 1.5 * u, 3 * u, 3 * u);
          ctx.fillRect(qb[0] - 1.5 * u, qb[1] - 1.5 * u, 3 * u, 3 * u);
          if (lines && (shown++ % Math.max(1, Math.ceil(M.count / 250)) === 0)) {
            ctx.globalAlpha = 0.55;
            ctx.lineWidth = u;
            ctx.beginPath(); ctx.moveTo(qa[0], qa[1]); ctx.lineTo(qb[0], qb[1]); ctx.stroke();
            ctx.globalAlpha = 1;
          }
        }
      }
      categories.forEach(function (c) { $('count-' + c.key).textContent = c.label + ' (' + counts[c.key] + ')'; });
      pairState.last = null;
      var info = $('pair-info');
      if (pairState.click) {
        var g = clickGeometry(I.P, mode, pairState.click, I.va, I.vb);
        pairState.last = g;
        var to = pairState.click.side === 'a' ? pb : pa, from = pairState.click.side === 'a' ? pa : pb;
        var toCam = pairState.click.side === 'a' ? b : a;
        var inImage = function (p) { return p && p[0] >= -0.5 && p[1] >= -0.5 && p[0] < toCam.width - 0.5 && p[1] < toCam.height - 0.5; };
        function curve(points, colour, dash) {
          ctx.save();
          ctx.beginPath();
          var region = pairState.click.side === 'a' ? [lay.offsetB, 0, wb, hb] : [0, 0, wa, ha];
          ctx.rect(region[0], region[1], region[2], region[3]);
          ctx.clip();
          ctx.strokeStyle = colour; ctx.lineWidth = 2.5 * u; ctx.setLineDash(dash.map(function (d) { return d * u; }));
          ctx.beginPath();
          var pen = false;
          points.forEach(function (p) {
            if (!p || !inImage(p)) { pen = false; return; }
            var q = to(p[0], p[1]);
            if (pen) ctx.lineTo(q[0], q[1]); else ctx.moveTo(q[0], q[1]);
            pen = true;
          });
          ctx.stroke();
          ctx.restore();
        }
        if (g.truth) curve(g.truth, '#ffe600', []);
        if (g.estimate) curve(g.estimate, modeColour(mode) === '#ffe14d' ? '#ff66cc' : modeColour(mode), [8, 5]);
        var c0 = from(pairState.click.px[0], pairState.click.px[1]);
        ctx.strokeStyle = '#fff'; ctx.lineWidth = 2 * u;
        var k = 9 * u;
        ctx.beginPath(); ctx.moveTo(c0[0] - k, c0[1]); ctx.lineTo(c0[0] + k, c0[1]); ctx.moveTo(c0[0], c0[1] - k); ctx.lineTo(c0[0], c0[1] + k); ctx.stroke();
        var text = 'Clicked (' + pairState.click.px[0].toFixed(1) + ', ' + pairState.click.px[1].toFixed(1) + ') in ' +
                   (pairState.click.side === 'a' ? a.name : b.name) + '. Yellow: its epipolar curve under the truth; dashed: under the estimate (' + mode + ')' +
                   (g.estimate ? '' : ', none: this method gave no full pose of both cameras') + '. ';
        if (g.transfer && g.transfer.point) {
          var t = to(g.transfer.point[0], g.transfer.point[1]);
          ctx.strokeStyle = '#000'; ctx.lineWidth = 4 * u; ctx.beginPath(); ctx.arc(t[0], t[1], 8 * u, 0, 2 * Math.PI); ctx.stroke();
          ctx.strokeStyle = '#fff'; ctx.lineWidth = 2 * u; ctx.beginPath(); ctx.arc(t[0], t[1], 8 * u, 0, 2 * Math.PI); ctx.stroke();
          text += 'White ring: where the point really is (from the rendered depth): (' + g.transfer.point[0].toFixed(1) + ', ' + g.transfer.point[1].toFixed(1) + ').';
        } else if (g.transfer) {
          text += 'No true correspondence: ' + g.transfer.why + '.';
        }
        info.textContent = text;
      }
      var stats = $('pair-stats');
      stats.innerHTML = '';
      var rows = R.modes.map(function (m) {
        var s = I.P.modes[m];
        return [m, s.matches, s.matches_evaluated ? pct(s.matches_correct, s.matches_evaluated) : '-', s.inliers,
                s.inliers_evaluated ? pct(s.inliers_correct, s.inliers_evaluated) : '-', s.success ? s.pair_type : (s.failure_reason || 'failed'),
                fmt(s.rotation_error_deg, 3, ' deg'), fmt(s.translation_direction_error_deg, 2, ' deg')];
      });
      stats.appendChild(el('h3', {}, 'This pair over all frames (the two-view estimate pools them)'));
      stats.appendChild(table(['method', 'matches', 'right', 'inliers', 'inliers right', 'outcome', 'rotation error', 'direction error'], rows));
    });
  }
  // Shows pair p at frame f for `mode` as if pixel px of camera a or b ('a', 'b') had been clicked.
  function clickPair(p, f, mode, side, px) {
    $('pair-select').value = String(p);
    $('pair-frame').value = String(f);
    $('pair-mode').value = mode;
    pairState.click = {side: side, px: px};
    return drawPair();
  }
  // Shades the cells of an overlap grid (1 = seen by the other camera): one pixel per cell on a
  // small canvas, scaled up smoothly over the photo.
  function shade(ctx, grid, ox, w, h) {
    var cells = bytes(grid.cells);
    var small = document.createElement('canvas');
    small.width = grid.width; small.height = grid.height;
    var sctx = small.getContext('2d');
    var img = sctx.createImageData(grid.width, grid.height);
    for (var i = 0; i < cells.length; ++i) {
      img.data[4 * i] = 80; img.data[4 * i + 1] = 160; img.data[4 * i + 2] = 255;
      img.data[4 * i + 3] = cells[i] ? 80 : 0;
    }
    sctx.putImageData(img, 0, 0);
    ctx.imageSmoothingEnabled = true;
    ctx.drawImage(small, ox, 0, w, h);
  }
  tabs.pairs = {shown: function () { drawPair(); }};

  // ---------------------------------------------------------------- 4. the pipeline
  function setupPipeline() {
    options($('pipeline-mode'), R.modes.map(function (m, i) { return {value: i, label: m}; }), 0);
    $('pipeline-mode').addEventListener('change', drawPipeline);
  }
  function step(body, title, intro) {
    var s = el('div', {class: 'step'});
    s.appendChild(el('h2', {}, title));
    if (intro) s.appendChild(el('p', {class: 'note'}, intro));
    body.appendChild(s);
    return s;
  }
  function svg(tag, attrs) {
    var e = document.createElementNS('http://www.w3.org/2000/svg', tag);
    for (var k in attrs) e.setAttribute(k, attrs[k]);
    return e;
  }
  function drawPipeline() {
    var mi = Number($('pipeline-mode').value);
    var P = R.pipeline.modes[mi];
    var body = $('pipeline-body');
    body.innerHTML = '';

    // 1. Keypoints per class, every method side by side: what the mask removes.
    var s1 = step(body, '1. Keypoints per class',
      'SIFT keypoints over all views, by the class of their pixel. Methods with the mask detect only on reliable classes (static structure), eroded by a few pixels so that no keypoint sits on a class border.');
    var perClass = {}, maxCount = 1;
    R.pipeline.modes.forEach(function (m) {
      (m.keypoints_per_class || []).forEach(function (e) { perClass[e[0]] = perClass[e[0]] || {}; perClass[e[0]][m.name] = e[1]; maxCount = Math.max(maxCount, e[1]); });
    });
    var rows = Object.keys(perClass).map(Number).sort(function (x, y) { return x - y; }).map(function (id) {
      var k = classById(id);
      var name = el('span');
      name.appendChild(el('span', {class: 'swatch', style: 'background:' + rgb(k.color)}));
      name.appendChild(document.createTextNode(k.name + (k.reliable ? ' (reliable)' : '')));
      var bars = el('div');
      R.pipeline.modes.forEach(function (m) {
        var n = perClass[id][m.name] || 0;
        var line = el('div');
        line.appendChild(el('span', {class: 'bar', style: 'width:' + Math.max(1, 300 * n / maxCount) + 'px;background:' + modeColour(m.name)}));
        line.appendChild(document.createTextNode(' ' + n + ' ' + m.name));
        bars.appendChild(line);
      });
      return [name, bars];
    });
    if (Object.keys(perClass).length === 1 && perClass[0]) {
      s1.appendChild(el('p', {class: 'note'}, 'No method of this run used labels, so the keypoints have no class here (calibrate with --semantics none,mask to compare).'));
    }
    s1.appendChild(table(['class', 'keypoints'], rows));
    s1.appendChild(el('p', {}, R.pipeline.modes.map(function (m) { return m.name + ': ' + m.keypoints + ' keypoints (' + m.mean_keypoints_per_image.toFixed(0) + ' per image)'; }).join('; ')));

    // 2. Matches and the two-view estimate per pair.
    var s2 = step(body, '2. Matches and inliers per camera pair',
      'Matches: ratio test and mutual check, pooled over the frames. Inliers: those the robust essential-matrix fit keeps. Right: by the ground truth (the keypoint lifted with its true depth lands within 2 px of its partner and is not occluded).');
    s2.appendChild(table(['pair', 'true overlap', 'matches', 'right', 'inliers', 'inliers right', 'outcome', 'rotation error', 'direction error'],
      R.pairs.map(function (p) {
        var m = p.modes[P.name];
        return [camName(p.a) + '-' + camName(p.b), p.overlap === null ? '-' : (100 * p.overlap).toFixed(0) + '%', m.matches,
                m.matches_evaluated ? pct(m.matches_correct, m.matches_evaluated) : '-', m.inliers,
                m.inliers_evaluated ? pct(m.inliers_correct, m.inliers_evaluated) : '-',
                m.success ? m.pair_type : (m.failure_reason || 'failed'), fmt(m.rotation_error_deg, 3, ' deg'), fmt(m.translation_direction_error_deg, 2, ' deg')];
      })));

    // 3. The view graph.
    var s3 = step(body, '3. The view graph',
      'One node per camera, one edge per pair with a relative pose. An edge is used when it has enough inliers and agrees with the others (rotation averaging); otherwise it is rejected, and the reason is given.');
    var n = R.cameras.length, W = 420, H = 300;
    var g = svg('svg', {width: W, height: H, style: 'background:#111'});
    var pos = R.cameras.map(function (_, i) {
      var a = -Math.PI / 2 + 2 * Math.PI * i / n;
      return [W / 2 + 0.38 * W * Math.cos(a), H / 2 + 0.38 * H * Math.sin(a)];
    });
    // Used edges green (thicker with more inliers), rejected poses red dashed, pairs without a
    // pose faint grey dotted; hover for the reason.
    P.edges.forEach(function (e) {
      var used = e.used, rejectedPose = !used && e.inliers > 0;
      var line = svg('line', {x1: pos[e.a][0], y1: pos[e.a][1], x2: pos[e.b][0], y2: pos[e.b][1],
        stroke: used ? '#39ff6a' : rejectedPose ? '#ff4d4d' : '#555', 'stroke-width': used ? 1 + Math.log10(1 + e.inliers) : 1.5,
        'stroke-dasharray': used ? '' : rejectedPose ? '6,4' : '2,4'});
      var title = svg('title', {});
      title.textContent = camName(e.a) + '-' + camName(e.b) + ': ' + e.status + ' (' + e.inliers + ' inliers)';
      line.appendChild(title);
      g.appendChild(line);
    });
    pos.forEach(function (p, i) {
      g.appendChild(svg('circle', {cx: p[0], cy: p[1], r: 16, fill: '#2a2d33', stroke: '#fff'}));
      var t = svg('text', {x: p[0], y: p[1] + 4, 'text-anchor': 'middle', fill: '#fff', 'font-size': 11});
      t.textContent = camName(i);
      g.appendChild(t);
    });
    s3.appendChild(g);
    s3.appendChild(el('p', {class: 'note'}, 'green: used (thicker: more inliers); red dashed: a pose the rig stage rejected; grey dotted: no pose (the pair failed). Hover an edge for why.'));
    s3.appendChild(table(['edge', 'inliers', 'rotation averaging residual', 'against the final rig', 'status'], P.edges.map(function (e) {
      var st = el('span', {class: e.used ? 'good' : 'bad'}, e.status);
      return [camName(e.a) + '-' + camName(e.b), e.inliers, fmt(e.rotation_residual_deg, 3, ' deg'),
              fmt(e.rotation_disagreement_deg, 3, ' deg'), st];
    })));
    s3.appendChild(el('p', {class: 'note'}, 'rotation averaging residual: how far the averaged rotations are from the pair\'s (0 where no other path of the graph constrains the pair); against the final rig: the finished rig\'s relative rotation against the pair\'s.'));

    // 4. Rotation averaging, then positions and the bundle adjustment.
    var s4 = step(body, '4. Rotation averaging',
      'Every camera\'s rotation in the rig from all used edges at once (robust, in the view graph), camera 0 being the rig frame. The error against the truth, before and after the bundle adjustment refines it.');
    s4.appendChild(table(['camera', 'after rotation averaging', 'after bundle adjustment'], P.cameras.map(function (c) {
      return [c.name, fmt(c.rotation_averaging_error_deg, 3, ' deg'), fmt(c.rotation_error_deg, 3, ' deg')];
    })));
    s4.appendChild(el('p', {}, P.rotation_outliers + ' edge(s) rejected as rotation outliers.'));

    var ba = P.bundle_adjustment;
    var s5 = step(body, '5. Bundle adjustment',
      'Tracks across cameras and frames, positions from the rig\'s motion, then every pose and point refined together to minimise the reprojection error; observations beyond 3 px are dropped and the problem solved again.');
    s5.appendChild(table(['tracks', 'points', 'observations', 'dropped', 'frames posed', 'RMS before', 'RMS after', 'median before', 'median after'],
      [[ba.tracks, ba.points, ba.observations, ba.filtered_observations, ba.frames_posed + ' / ' + ba.frames,
        fmt(ba.initial_rms_px, 2, ' px'), fmt(ba.final_rms_px, 3, ' px'), fmt(ba.initial_median_px, 2, ' px'), fmt(ba.final_median_px, 3, ' px')]]));
    if (ba.initial_residuals) s5.appendChild(histogram([ba.initial_residuals, ba.final_residuals], ['#ff9a3c', '#39ff6a'], ['before (initial poses)', 'after']));

    var s6 = step(body, '6. The result: each camera against the truth',
      't_dir_std: how well the images fix the direction of the camera from camera 0 (one standard deviation from the bundle adjustment\'s covariance), known without any truth. Position error: after fitting the scale, as rigsim evaluate does.');
    s6.appendChild(table(['camera', 'status', 'rotation error', 'direction error', 't_dir_std', 'position error', 'observations'], P.cameras.map(function (c) {
      return [c.name, c.status, fmt(c.rotation_error_deg, 3, ' deg'), fmt(c.translation_direction_error_deg, 2, ' deg'),
              fmt(c.direction_std_deg, 3, ' deg'), fmt(c.position_error_m, 3, ' m'), c.observations];
    })));
    s6.appendChild(el('p', {}, 'Scale: ' + P.scale + '.'));
    P.warnings.forEach(function (w) { s6.appendChild(el('p', {class: 'bad'}, 'warning: ' + w)); });
  }
  // Log-x histogram of residuals (report_pipeline.cc Histogram), several series.
  function histogram(series, colours, names) {
    var W = 560, H = 200, L = 40, B = 30;
    var g = svg('svg', {width: W, height: H + 20, style: 'background:#111'});
    var edges = series[0].edges, nb = series[0].counts.length;
    var maxC = 1;
    series.forEach(function (s) { s.counts.forEach(function (c) { maxC = Math.max(maxC, c); }); });
    var bw = (W - L - 10) / nb;
    series.forEach(function (s, k) {
      s.counts.forEach(function (c, i) {
        var h = (H - B) * c / maxC;
        g.appendChild(svg('rect', {x: L + i * bw + k * bw / series.length, y: H - B - h, width: bw / series.length, height: h, fill: colours[k]}));
      });
    });
    for (var i = 0; i <= nb; i += 5) {
      var t = svg('text', {x: L + i * bw, y: H - B + 14, fill: '#aaa', 'font-size': 10, 'text-anchor': 'middle'});
      t.textContent = edges[i] >= 1 ? edges[i].toFixed(0) : edges[i].toPrecision(1);
      g.appendChild(t);
    }
    var label = svg('text', {x: W / 2, y: H - 2, fill: '#aaa', 'font-size': 11, 'text-anchor': 'middle'});
    label.textContent = 'reprojection error (px, log scale)';
    g.appendChild(label);
    names.forEach(function (nm, k) {
      g.appendChild(svg('rect', {x: W - 290, y: 8 + 16 * k, width: 10, height: 10, fill: colours[k]}));
      var t = svg('text', {x: W - 275, y: 17 + 16 * k, fill: '#ddd', 'font-size': 11});
      t.textContent = nm + ' (' + series[k].total + ' observations)';
      g.appendChild(t);
    });
    return g;
  }
  tabs.pipeline = {shown: function () { drawPipeline(); }};

  // ---------------------------------------------------------------- 5. numbers
  function setupNumbers() {
    var body = $('numbers-body');
    body.innerHTML = '';
    var T = R.pipeline.tables;
    body.appendChild(el('h2', {}, 'Relative pose of every camera pair (as rigsim calibrate prints it)'));
    body.appendChild(el('pre', {}, T.pairs));
    body.appendChild(el('h2', {}, 'Every camera\'s pose'));
    body.appendChild(el('pre', {}, T.rig + '\n' + T.rig_summary));
    if (T.times) {
      body.appendChild(el('h2', {}, 'Capture times: each camera\'s offset from camera 0 and its rolling-shutter readout, as the images show them'));
      body.appendChild(el('pre', {}, T.times));
    }
    if (T.evaluate) {
      body.appendChild(el('h2', {}, 'Scores against the truth (as rigsim evaluate prints them)'));
      body.appendChild(el('pre', {}, T.evaluate));
    }
    if (R.sweep) {
      body.appendChild(el('h2', {}, 'Sweep: ' + R.sweep.folder));
      (R.sweep.plots || []).forEach(function (p) { body.appendChild(el('img', {class: 'plot', src: p, alt: p})); });
      if (R.sweep.summary) {
        var d = el('details');
        d.appendChild(el('summary', {}, 'summary.json'));
        d.appendChild(el('pre', {}, JSON.stringify(R.sweep.summary, null, 2)));
        body.appendChild(d);
      }
      if (R.sweep.report_md) {
        var r = el('details', {open: ''});
        r.appendChild(el('summary', {}, 'report.md'));
        r.appendChild(el('pre', {}, R.sweep.report_md));
        body.appendChild(r);
      }
    }
  }
  tabs.numbers = {};

  // ---------------------------------------------------------------- self-test (?selftest=1)
  // Recomputes the C++'s reference values (report_pairs.cc) with the page's own code, through the
  // pair view's click path, checks that the 3D view drew, and writes the results into #selftest.
  function selftest() {
    var out = {done: false};
    var drawnViews = 0;
    var ref = R.selftest;
    var wait = scene3d.ready || Promise.resolve();
    return wait.then(function () {
      scene3d.render();
      var gl = scene3d.renderer.getContext();
      var w = gl.drawingBufferWidth, h = gl.drawingBufferHeight;
      var px = new Uint8Array(w * h * 4);
      gl.readPixels(0, 0, w, h, gl.RGBA, gl.UNSIGNED_BYTE, px);
      var drawn = 0;
      for (var i = 0; i < w * h; ++i) {
        if (Math.abs(px[4 * i] - 0x15) + Math.abs(px[4 * i + 1] - 0x17) + Math.abs(px[4 * i + 2] - 0x1b) > 12) drawn++;
      }
      out.webgl = {width: w, height: h, drawn_fraction: w * h ? drawn / (w * h) : 0};
      if (!ref) { out.reference = null; return; }
      var P = R.pairs[ref.pair];
      var a = R.cameras[P.a], b = R.cameras[P.b];
      function maxDiff(js, cpp) {
        if (!cpp) return null;
        if (js.length !== cpp.length) return Infinity;
        var d = 0;
        for (var i = 0; i < js.length; ++i) {
          if (!js[i] !== !cpp[i]) return Infinity;
          if (js[i]) d = Math.max(d, Math.hypot(js[i][0] - cpp[i][0], js[i][1] - cpp[i][1]));
        }
        return d;
      }
      var truth = epipolarCurve(a, ref.px, b, pose(P.b_from_a_truth), ref.depths);
      out.curve_truth_max_px = maxDiff(truth, ref.curve_truth);
      out.curve_truth_points = ref.curve_truth.filter(function (p) { return p; }).length;
      var m = P.modes[ref.mode];
      out.curve_estimate_max_px = m.b_from_a_rig ? maxDiff(epipolarCurve(a, ref.px, b, pose(m.b_from_a_rig), ref.depths), ref.curve_estimate) : null;
      // The same click through the pair view.
      return clickPair(ref.pair, ref.frame, ref.mode, 'a', ref.px).then(function () {
        var g = pairState.last;
        // The view's dense curve passes through the C++'s points: each reference point lies within
        // a fraction of a pixel of the drawn polyline.
        function nearCurve(dense, cpp) {
          if (!cpp) return null;
          var worst = 0;
          cpp.forEach(function (q, k) {
            if (!q || k === cpp.length - 1) return;
            var best = Infinity;
            for (var i = 0; i + 1 < dense.length; ++i) {
              var p0 = dense[i], p1 = dense[i + 1];
              if (!p0 || !p1) continue;
              var dx = p1[0] - p0[0], dy = p1[1] - p0[1], L2 = dx * dx + dy * dy;
              var t = L2 > 0 ? Math.max(0, Math.min(1, ((q[0] - p0[0]) * dx + (q[1] - p0[1]) * dy) / L2)) : 0;
              best = Math.min(best, Math.hypot(p0[0] + t * dx - q[0], p0[1] + t * dy - q[1]));
            }
            worst = Math.max(worst, best);
          });
          return worst;
        }
        out.view_curve_truth_px = nearCurve(g.truth || [], ref.curve_truth);
        out.view_curve_estimate_px = g.estimate ? nearCurve(g.estimate, ref.curve_estimate) : null;
        var tp = g.transfer && g.transfer.point;
        out.true_point = tp;
        out.true_point_px = ref.true_point && tp ? Math.hypot(tp[0] - ref.true_point[0], tp[1] - ref.true_point[1]) : null;
        out.true_point_expected = ref.true_point;
      });
    }).then(function () {
      // Every camera's first view under each base image, and the pipeline of every method: no error.
      drawnViews = 0;
      var chain = Promise.resolve();
      R.cameras.forEach(function (_, c) {
        ['rgb', 'depth', 'instances'].forEach(function (base) {
          chain = chain.then(function () {
            $('view-camera').value = String(c); $('view-frame').value = '0'; $('view-base').value = base;
            return drawView().then(function () { drawnViews++; });
          });
        });
      });
      return chain.then(function () {
        out.views_drawn = drawnViews;
        R.modes.forEach(function (_, m) { $('pipeline-mode').value = String(m); drawPipeline(); });
        out.pipeline_steps = document.querySelectorAll('#pipeline-body .step').length;
        // The view graph's edge table of the method drawn last: a row per camera pair, each with its status.
        var edgeTable = null;
        document.querySelectorAll('#pipeline-body table').forEach(function (t) {
          if (t.rows.length && /against the final rig/.test(t.rows[0].textContent)) edgeTable = t;
        });
        var rows = edgeTable ? Array.prototype.slice.call(edgeTable.rows, 1) : [];
        out.edge_rows = rows.length;
        out.edge_rows_expected = R.pipeline.modes[Number($('pipeline-mode').value)].edges.length;
        out.edge_rows_with_status = rows.filter(function (r) { return r.cells.length === 5 && r.cells[4].textContent.length > 0; }).length;
        // The Numbers tab's tables wrap on a narrow page instead of running off its side.
        showTab('numbers');
        var nb = $('numbers-body');
        nb.style.width = '360px';
        var pres = nb.querySelectorAll('pre'), overflow = 0;
        pres.forEach(function (p) { overflow = Math.max(overflow, p.scrollWidth - p.clientWidth); });
        out.numbers_tables = pres.length;
        out.numbers_overflow_px = overflow;
        nb.style.width = '';
        showTab('scene');
      });
    }).catch(function (e) { out.exception = String(e && e.stack || e); }).then(function () {
      out.errors = window.RIGSIM_ERRORS.slice();
      out.done = true;
      $('selftest').textContent = JSON.stringify(out);
      document.title = 'selftest done';
    });
  }

  // ---------------------------------------------------------------- start
  function start() {
    R = store.report;
    if (!R) { document.body.textContent = 'data/report.js is missing: the report is incomplete.'; return; }
    $('about').textContent = 'Dataset ' + R.dataset + ': ' + R.cameras.length + ' cameras, ' + R.frames.length +
      ' frames; methods ' + R.modes.join(', ') + '; labels ' + R.labels + (R.has_truth ? '; compared with the rendered truth' : '; no ground truth') +
      '. Made by ' + (R.command || 'rigsim') + ' (rigsim ' + R.tool_version + ').';
    setupScene();
    setupViews();
    setupPairs();
    setupPipeline();
    setupNumbers();
    var footer = $('footer');
    footer.textContent = 'three.js r111 (MIT licence, three/LICENSE). ' + (R.warnings.length ? 'Warnings: ' + R.warnings.join('; ') : '');
    window.addEventListener('hashchange', function () { showTab(location.hash.slice(1)); });
    showTab(location.hash.slice(1) || 'scene');
    if (/[?&]selftest=1/.test(location.search)) selftest();
  }

  return {put: put, load: load, start: start, clickPair: clickPair, openView: openView,
          geometry: {imgFromCam: imgFromCam, camFromImg: camFromImg, epipolarCurve: epipolarCurve}};
})();
