/* strainwave report: a small self-contained WebGL viewer of one stress field (no network, no library).
   Each canvas of class sw-view reads the JSON script element named by its data-source attribute:
   positions (float32, xyz), scalars (float32), indices (uint32), all base64, and the colour range.
   Drag rotates, the wheel zooms, a double click resets the view. */
(function () {
  "use strict";
  function decode(b64, Type) {
    var bin = atob(b64), bytes = new Uint8Array(bin.length);
    for (var i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
    return new Type(bytes.buffer);
  }
  var VS = "attribute vec3 p; attribute vec3 n; attribute float s; uniform mat4 m; uniform mat4 pr;" +
    "varying float vs; varying float vl; void main(){ vec4 q = m * vec4(p, 1.0); gl_Position = pr * q;" +
    "vec3 nn = normalize((m * vec4(n, 0.0)).xyz); vl = 0.35 + 0.65 * abs(nn.z); vs = s; }";
  var FS = "precision mediump float; varying float vs; varying float vl; uniform vec2 range;" +
    "vec3 turbo(float x){ x = clamp(x, 0.0, 1.0); vec4 v4 = vec4(1.0, x, x * x, x * x * x); vec2 v2 = v4.zw * v4.z;" +
    "return vec3(dot(v4, vec4(0.13572138, 4.61539260, -42.66032258, 132.13108234)) + dot(v2, vec2(-152.94239396, 59.28637943))," +
    "dot(v4, vec4(0.09140261, 2.19418839, 4.84296658, -14.18503333)) + dot(v2, vec2(4.27729857, 2.82956604))," +
    "dot(v4, vec4(0.10667330, 12.64194608, -60.58204836, 110.36276771)) + dot(v2, vec2(-89.90310912, 27.34824973))); }" +
    "void main(){ float t = (vs - range.x) / max(range.y - range.x, 1e-30); gl_FragColor = vec4(turbo(t) * vl, 1.0); }";
  function shader(gl, type, src) {
    var sh = gl.createShader(type);
    gl.shaderSource(sh, src);
    gl.compileShader(sh);
    if (!gl.getShaderParameter(sh, gl.COMPILE_STATUS)) throw new Error(gl.getShaderInfoLog(sh));
    return sh;
  }
  function mul(a, b) {  /* column-major 4x4: a * b */
    var o = new Float32Array(16);
    for (var c = 0; c < 4; c++) for (var r = 0; r < 4; r++) {
      var v = 0;
      for (var k = 0; k < 4; k++) v += a[k * 4 + r] * b[c * 4 + k];
      o[c * 4 + r] = v;
    }
    return o;
  }
  function rotX(t) { var c = Math.cos(t), s = Math.sin(t); return new Float32Array([1,0,0,0, 0,c,s,0, 0,-s,c,0, 0,0,0,1]); }
  function rotY(t) { var c = Math.cos(t), s = Math.sin(t); return new Float32Array([c,0,-s,0, 0,1,0,0, s,0,c,0, 0,0,0,1]); }
  function view(canvas) {
    var data = JSON.parse(document.getElementById(canvas.getAttribute("data-source")).textContent);
    var pos = decode(data.positions, Float32Array), sca = decode(data.scalars, Float32Array),
        idx = decode(data.indices, Uint32Array);
    var nv = sca.length, nrm = new Float32Array(3 * nv);
    for (var t = 0; t < idx.length; t += 3) {  /* area-weighted vertex normals */
      var a = 3 * idx[t], b = 3 * idx[t + 1], c = 3 * idx[t + 2];
      var ux = pos[b] - pos[a], uy = pos[b + 1] - pos[a + 1], uz = pos[b + 2] - pos[a + 2];
      var vx = pos[c] - pos[a], vy = pos[c + 1] - pos[a + 1], vz = pos[c + 2] - pos[a + 2];
      var nx = uy * vz - uz * vy, ny = uz * vx - ux * vz, nz = ux * vy - uy * vx;
      for (var j = 0; j < 3; j++) { var q = 3 * idx[t + j]; nrm[q] += nx; nrm[q + 1] += ny; nrm[q + 2] += nz; }
    }
    /* expand to a triangle list: WebGL 1 without extensions indexes at most 65535 vertices */
    var n = idx.length, P = new Float32Array(3 * n), N = new Float32Array(3 * n), S = new Float32Array(n);
    for (var i = 0; i < n; i++) {
      var k = idx[i];
      for (var d = 0; d < 3; d++) { P[3 * i + d] = pos[3 * k + d]; N[3 * i + d] = nrm[3 * k + d]; }
      S[i] = sca[k];
    }
    var gl = canvas.getContext("webgl", {preserveDrawingBuffer: true, antialias: true});
    if (!gl) {  /* no WebGL: say so in place of a blank canvas (the PNG above shows the same field) */
      var note = canvas.parentNode.querySelector(".nowebgl");
      if (note) note.style.display = "block";
      canvas.style.display = "none";
      return;
    }
    var prog = gl.createProgram();
    gl.attachShader(prog, shader(gl, gl.VERTEX_SHADER, VS));
    gl.attachShader(prog, shader(gl, gl.FRAGMENT_SHADER, FS));
    gl.linkProgram(prog);
    if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) throw new Error(gl.getProgramInfoLog(prog));
    gl.useProgram(prog);
    [["p", P, 3], ["n", N, 3], ["s", S, 1]].forEach(function (a) {
      var buf = gl.createBuffer(), loc = gl.getAttribLocation(prog, a[0]);
      gl.bindBuffer(gl.ARRAY_BUFFER, buf);
      gl.bufferData(gl.ARRAY_BUFFER, a[1], gl.STATIC_DRAW);
      gl.enableVertexAttribArray(loc);
      gl.vertexAttribPointer(loc, a[2], gl.FLOAT, false, 0, 0);
    });
    gl.uniform2f(gl.getUniformLocation(prog, "range"), data.range[0], data.range[1]);
    gl.enable(gl.DEPTH_TEST);
    var home = data.home || [-0.6, 0.6], state = {ax: home[0], ay: home[1], zoom: 1.0};
    function draw() {
      gl.viewport(0, 0, canvas.width, canvas.height);
      gl.clearColor(1, 1, 1, 1);
      gl.clear(gl.COLOR_BUFFER_BIT | gl.DEPTH_BUFFER_BIT);
      var m = mul(rotX(state.ax), rotY(state.ay));
      var aspect = canvas.width / canvas.height, s = 0.95 * state.zoom;
      /* orthographic: the model is centred and scaled into the unit sphere by the writer */
      var pr = new Float32Array([s / aspect,0,0,0, 0,s,0,0, 0,0,-0.5,0, 0,0,0,1]);
      gl.uniformMatrix4fv(gl.getUniformLocation(prog, "m"), false, m);
      gl.uniformMatrix4fv(gl.getUniformLocation(prog, "pr"), false, pr);
      gl.drawArrays(gl.TRIANGLES, 0, n);
      canvas.setAttribute("data-rendered", String(n / 3));
    }
    var drag = null;
    canvas.addEventListener("mousedown", function (e) { drag = [e.clientX, e.clientY]; });
    window.addEventListener("mouseup", function () { drag = null; });
    canvas.addEventListener("mousemove", function (e) {
      if (!drag) return;
      state.ay += 0.01 * (e.clientX - drag[0]); state.ax += 0.01 * (e.clientY - drag[1]);
      drag = [e.clientX, e.clientY]; draw();
    });
    canvas.addEventListener("wheel", function (e) {
      e.preventDefault(); state.zoom *= Math.exp(-0.001 * e.deltaY); draw();
    }, {passive: false});
    canvas.addEventListener("dblclick", function () { state = {ax: home[0], ay: home[1], zoom: 1.0}; draw(); });
    draw();
  }
  function start() {
    var canvases = document.querySelectorAll("canvas.sw-view");
    for (var i = 0; i < canvases.length; i++) view(canvases[i]);
  }
  if (document.readyState === "loading") document.addEventListener("DOMContentLoaded", start); else start();
})();
