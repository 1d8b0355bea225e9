// The viewer of an exported dynamic painting (issue 17): WebGL2 draws the fragment shader that
// dynpaint_addon/nodegraph/glsl_codegen.py generated from the pipeline's graph; this script
// only loads the images, sets the uniforms and moves the lights. The page's data (#dp-data)
// comes from dynpaint_addon/web/page.py. No network, no library.
"use strict";

(function () {
  const PAGE = JSON.parse(document.getElementById("dp-data").textContent);
  const QUERY = new URLSearchParams(location.search);
  const EMBED = QUERY.has("embed");
  const canvas = document.getElementById("painting");
  const message = document.getElementById("message");
  const BACKDROP = [0.0116, 0.0116, 0.0116];          // #1b1b1b, linear

  // -- the lights: each has a place (x, y, h) in image widths from the painting's centre ------
  // A point light sits at its place; a sun shines from the direction of its place, as if it
  // were there: dragging puts the light over the pointer, the height lifts it.
  function placeOf(light) {
    const [x, y, z] = light.vector;
    if (light.kind === "point") return [x, y, z];
    const n = Math.hypot(x, y, z) || 1;
    return [x / n, y / n, z / n];
  }
  const lights = PAGE.lights.map((lt) => ({ ...lt, on: true, place: placeOf(lt) }));
  const state = { key: 0, playing: false, phase: 0, frame: 0, look: 0, dirty: true,
                  drawScale: 1, fullFrameMs: 0, measure: true, lastInput: -1e9,
                  pageFrame: 0, framesPlaying: !!PAGE.frames };

  function lightVector(lt) {
    const [x, y, h] = lt.place;
    if (lt.kind === "point") return [x, y, h];
    const n = Math.hypot(x, y, h) || 1;
    return [x / n, y / n, h / n];
  }

  // -- WebGL2 ------------------------------------------------------------------------------
  const gl = canvas.getContext("webgl2", { antialias: false, premultipliedAlpha: false,
                                           preserveDrawingBuffer: true });
  function fail(text) {
    message.textContent = text;
    message.hidden = false;
    document.body.dataset.state = "failed";
    api.error = text;
  }
  const api = { ready: null, error: null, frames: 0, state, lights };
  const paintings = [];           // the painting, or each layer of a scene (back first)
  window.dynamicPainting = api;

  // -- the copy of the painting this device draws (web/device_fit.py, chosen_copy; its
  // constants in PAGE.device_rule): the largest whose textures the GPU takes
  // (MAX_TEXTURE_SIZE, and its viewports) and whose estimated memory is within a share of the
  // device's (navigator.deviceMemory, which browsers round and cap at 8 GB, and some do not
  // say). Tests imitate a smaller device: ?max_texture=PX, ?device_gb=GB.
  function deviceLimits() {
    const asked = (name) => { const v = parseFloat(QUERY.get(name)); return v > 0 ? v : null; };
    const dims = gl ? [gl.getParameter(gl.MAX_TEXTURE_SIZE), ...gl.getParameter(gl.MAX_VIEWPORT_DIMS)]
      : [Infinity];
    const rule = PAGE.device_rule;
    const gb = asked("device_gb") || navigator.deviceMemory || rule.unreported_gb;
    return { side: Math.min(...dims, asked("max_texture") || Infinity),
             bytes: gb * 2 ** 30 * rule.gpu_share };
  }
  function chooseLevel(page) {
    const limits = deviceLimits();
    const levels = [page, ...page.smaller];
    const fits = (d) => d.fit.side <= limits.side && d.fit.bytes <= limits.bytes;
    const data = levels.find(fits) || levels[levels.length - 1];
    page.smaller = null;                   // the others are not kept
    api.level = { width: data.width, height: data.height, full: [page.width, page.height],
                  maxTexture: limits.side, budgetMB: Math.round(limits.bytes / 2 ** 20),
                  neededMB: Math.round(data.fit.bytes / 2 ** 20),
                  fits: fits(data) };
    return data;
  }
  const DATA = chooseLevel(PAGE);

  // The info line: the painting's size, and why this device draws a smaller copy of it.
  function levelInfo() {
    const { width, height, full, maxTexture, budgetMB, neededMB, fits } = api.level;
    let text = `${full[0]} × ${full[1]} px`;
    if (width !== full[0] || height !== full[1] || !fits) {
      const limit = isFinite(maxTexture) ? `textures up to ${maxTexture} px` : "";
      text += ` · drawn at ${width} × ${height}: this device draws ${limit}` +
        `${limit ? " and " : ""}about ${budgetMB} MB of images` +
        (fits ? "" : ` (this copy needs about ${neededMB} MB: it may not draw)`);
    }
    return text + (DATA.shadows ? ` · shadows K = ${DATA.steps}` : "");
  }

  const VERTEX = "#version 300 es\nvoid main() {\n" +
    "  vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));\n" +
    "  gl_Position = vec4(p * 2.0 - 1.0, 0.0, 1.0);\n}\n";

  function compile(kind, source) {
    const sh = gl.createShader(kind);
    gl.shaderSource(sh, source);
    gl.compileShader(sh);
    if (!gl.getShaderParameter(sh, gl.COMPILE_STATUS)) {
      throw new Error("the painting's shader did not compile: " + gl.getShaderInfoLog(sh));
    }
    return sh;
  }

  function program(source) {
    const prog = gl.createProgram();
    gl.attachShader(prog, compile(gl.VERTEX_SHADER, VERTEX));
    gl.attachShader(prog, compile(gl.FRAGMENT_SHADER, source));
    gl.linkProgram(prog);
    if (!gl.getProgramParameter(prog, gl.LINK_STATUS)) {
      throw new Error("the painting's shader did not link: " + gl.getProgramInfoLog(prog));
    }
    return prog;
  }

  // -- images: base64 → inflate → byte planes → row deltas → RGBA texture --------------------
  // Inflated here, synchronously (RFC 1950/1951), not by DecompressionStream: the first frame is
  // then drawn before the page's load event, so a screenshot taken at load shows the painting.
  const LENGTH_BASE = [3, 4, 5, 6, 7, 8, 9, 10, 11, 13, 15, 17, 19, 23, 27, 31, 35, 43, 51, 59,
                       67, 83, 99, 115, 131, 163, 195, 227, 258];
  const LENGTH_BITS = [0, 0, 0, 0, 0, 0, 0, 0, 1, 1, 1, 1, 2, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4,
                       5, 5, 5, 5, 0];
  const DIST_BASE = [1, 2, 3, 4, 5, 7, 9, 13, 17, 25, 33, 49, 65, 97, 129, 193, 257, 385, 513,
                     769, 1025, 1537, 2049, 3073, 4097, 6145, 8193, 12289, 16385, 24577];
  const DIST_BITS = [0, 0, 0, 0, 1, 1, 2, 2, 3, 3, 4, 4, 5, 5, 6, 6, 7, 7, 8, 8, 9, 9, 10, 10,
                     11, 11, 12, 12, 13, 13];
  const CODE_ORDER = [16, 17, 18, 0, 8, 7, 9, 6, 10, 5, 11, 4, 12, 3, 13, 2, 14, 1, 15];

  // A canonical Huffman code as one lookup table over its longest code's bits: entry =
  // symbol << 4 | code length (codes are packed least significant bit first).
  function huffman(lengths) {
    const max = Math.max(1, ...lengths), table = new Int32Array(1 << max).fill(-1);
    const count = new Array(16).fill(0), next = new Array(16).fill(0);
    lengths.forEach((l) => { if (l) count[l]++; });
    for (let b = 1, code = 0; b <= max; b++) { code = (code + count[b - 1]) << 1; next[b] = code; }
    lengths.forEach((l, symbol) => {
      if (!l) return;
      let code = next[l]++, reversed = 0;
      for (let i = 0; i < l; i++) { reversed = (reversed << 1) | (code & 1); code >>= 1; }
      for (let k = reversed; k < table.length; k += 1 << l) table[k] = (symbol << 4) | l;
    });
    return { table, max };
  }
  const FIXED_LENGTHS = huffman([...Array(288)].map((_, i) =>
    i < 144 ? 8 : i < 256 ? 9 : i < 280 ? 7 : 8));
  const FIXED_DISTANCES = huffman(new Array(30).fill(5));

  function inflate(b64) {
    const text = atob(b64);
    const src = new Uint8Array(text.length);
    for (let i = 0; i < text.length; i++) src[i] = text.charCodeAt(i);
    let pos = 2, bits = 0, count = 0, out = new Uint8Array(4 * src.length + 1024), size = 0;
    const need = (n) => { while (count < n) { bits |= (src[pos++] | 0) << count; count += 8; } };
    const take = (n) => {
      need(n);
      const v = bits & ((1 << n) - 1);
      bits >>>= n; count -= n;
      return v;
    };
    const symbol = (code) => {
      need(code.max);
      const e = code.table[bits & ((1 << code.max) - 1)];
      if (e < 0) throw new Error("a painting image is damaged (bad deflate code)");
      bits >>>= e & 15; count -= e & 15;
      return e >> 4;
    };
    const room = (n) => {
      if (size + n <= out.length) return;
      const bigger = new Uint8Array(Math.max(2 * out.length, size + n));
      bigger.set(out.subarray(0, size));
      out = bigger;
    };
    let last = 0;
    while (!last) {
      last = take(1);
      const type = take(2);
      if (type === 0) {                              // stored: whole bytes after the header
        pos -= count >> 3; bits = count = 0;
        const n = src[pos] | (src[pos + 1] << 8);
        pos += 4;
        room(n);
        out.set(src.subarray(pos, pos + n), size);
        size += n; pos += n;
        continue;
      }
      let lengths = FIXED_LENGTHS, distances = FIXED_DISTANCES;
      if (type === 2) {
        const nlen = take(5) + 257, ndist = take(5) + 1, ncode = take(4) + 4;
        const codeLengths = new Array(19).fill(0);
        for (let i = 0; i < ncode; i++) codeLengths[CODE_ORDER[i]] = take(3);
        const lengthCode = huffman(codeLengths), all = [];
        while (all.length < nlen + ndist) {
          const s = symbol(lengthCode);
          if (s < 16) all.push(s);
          else if (s === 16) all.push(...new Array(3 + take(2)).fill(all[all.length - 1]));
          else all.push(...new Array(s === 17 ? 3 + take(3) : 11 + take(7)).fill(0));
        }
        lengths = huffman(all.slice(0, nlen));
        distances = huffman(all.slice(nlen));
      } else if (type !== 1) {
        throw new Error("a painting image is damaged (bad deflate block)");
      }
      for (;;) {
        const s = symbol(lengths);
        if (s < 256) { room(1); out[size++] = s; continue; }
        if (s === 256) break;
        const n = LENGTH_BASE[s - 257] + take(LENGTH_BITS[s - 257]);
        const d = symbol(distances), back = DIST_BASE[d] + take(DIST_BITS[d]);
        room(n);
        for (let i = 0; i < n; i++, size++) out[size] = out[size - back];
      }
    }
    return out.subarray(0, size);
  }

  const SIZES = { u8: 1, u16: 2, f16: 2, f32: 4 };
  const ARRAYS = { 1: Uint8Array, 2: Uint16Array, 4: Uint32Array };

  function codesOf(tex, planes) {
    const size = SIZES[tex.format], n = tex.width * tex.height * tex.channels;
    const bytes = new Uint8Array(n * size);
    for (let k = 0; k < size; k++) {
      for (let i = 0, j = k * n; i < n; i++, j++) bytes[i * size + k] = planes[j];
    }
    const codes = new ARRAYS[size](bytes.buffer);
    const row = tex.width * tex.channels, c = tex.channels;
    for (let r = 0; r < tex.height; r++) {          // undo the row deltas (wrapping sums)
      for (let i = r * row + c, end = (r + 1) * row; i < end; i++) codes[i] += codes[i - c];
    }
    return codes;
  }

  function rgbaOf(tex, codes) {
    // grey → (g, g, g), grey + alpha → (g, g, g, a), missing alpha → 1 (core's ImageData)
    const n = tex.width * tex.height, c = tex.channels;
    const u16 = tex.format === "u16", f32 = tex.format === "f32";
    const out = u16 || f32 ? new Float32Array(n * 4) : new ARRAYS[SIZES[tex.format]](n * 4);
    const src = f32 ? new Float32Array(codes.buffer) : codes;
    const one = { u8: 255, u16: 1, f16: 0x3c00, f32: 1 }[tex.format];
    const scale = u16 ? 1 / 65535 : 1;
    for (let i = 0; i < n; i++) {
      const s = i * c, d = i * 4;
      const r = src[s] * scale;
      const g = c >= 3 ? src[s + 1] * scale : r, b = c >= 3 ? src[s + 2] * scale : r;
      out[d] = r; out[d + 1] = g; out[d + 2] = b;
      out[d + 3] = c === 2 || c === 4 ? src[s + c - 1] * scale : one;
    }
    return out;
  }

  // sRGB codes → linear light (§0), for 16-bit colour images (no 16-bit sRGB texture exists).
  function srgbToLinear(c) {
    return c <= 0.04045 ? c / 12.92 : Math.pow((c + 0.055) / 1.055, 2.4);
  }

  // A texture of one image → {texture, filterable}. The GPU decodes 8-bit sRGB colour images
  // itself (SRGB8_ALPHA8: each texel to linear before filtering, as the core decodes then
  // interpolates); 16-bit colour images are decoded here, once; data stays as stored. Floats
  // are filterable where the browser says so (OES_texture_float_linear), halves and bytes
  // always.
  const floatLinear = !!(gl && gl.getExtension("OES_texture_float_linear"));
  function texture(tex, asCodes = false) {
    const rgba = rgbaOf(tex, codesOf(tex, inflate(tex.data)));
    const srgb = tex.srgb && !asCodes;     // asCodes: a shader mixes the codes themselves
    if (srgb && tex.format === "u16") {
      for (let i = 0; i < rgba.length; i++) if (i % 4 !== 3) rgba[i] = srgbToLinear(rgba[i]);
    }
    const t = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, t);
    gl.pixelStorei(gl.UNPACK_ALIGNMENT, 1);
    const [internal, type] = tex.format === "u8" ? [srgb ? gl.SRGB8_ALPHA8 : gl.RGBA8,
                                                    gl.UNSIGNED_BYTE]
      : tex.format === "f16" ? [gl.RGBA16F, gl.HALF_FLOAT] : [gl.RGBA32F, gl.FLOAT];
    gl.texImage2D(gl.TEXTURE_2D, 0, internal, tex.width, tex.height, 0, gl.RGBA, type, rgba);
    unfiltered();
    return { texture: t, filterable: type !== gl.FLOAT || floatLinear };
  }

  // The bound texture read texel by texel, edges clamped: complete without mipmaps for any
  // format (each draw binds a sampler of its own over this, samplerFor).
  function unfiltered() {
    for (const [k, v] of [[gl.TEXTURE_MIN_FILTER, gl.NEAREST], [gl.TEXTURE_MAG_FILTER, gl.NEAREST],
                          [gl.TEXTURE_WRAP_S, gl.CLAMP_TO_EDGE], [gl.TEXTURE_WRAP_T, gl.CLAMP_TO_EDGE]]) {
      gl.texParameteri(gl.TEXTURE_2D, k, v);
    }
  }

  // One sampler per wrap and filter: a program's lookups choose the wrap of each image
  // (DATA.samplers, the generator's `wraps`), the texture's format whether it is filtered.
  const WRAP_MODES = { REPEAT: "REPEAT", EXTEND: "CLAMP_TO_EDGE", MIRROR: "MIRRORED_REPEAT" };
  const samplers = {};
  function samplerFor(wrap, linear) {
    const key = wrap + linear;
    if (!samplers[key]) {
      const s = samplers[key] = gl.createSampler();
      const filter = linear ? gl.LINEAR : gl.NEAREST;
      gl.samplerParameteri(s, gl.TEXTURE_MIN_FILTER, filter);
      gl.samplerParameteri(s, gl.TEXTURE_MAG_FILTER, filter);
      gl.samplerParameteri(s, gl.TEXTURE_WRAP_S, gl[WRAP_MODES[wrap]]);
      gl.samplerParameteri(s, gl.TEXTURE_WRAP_T, gl[WRAP_MODES[wrap]]);
    }
    return samplers[key];
  }

  // -- shadows: each light's cos-θ term (§6) drawn into a texture of its own when that light,
  // the look or K changes — at a fraction of the painting's pixels while the light moves, at
  // its full size once it stops — and read by the frame like any image (issue 29). A frame
  // whose lights did not move marches nothing. In a scene of layers (§15) the pass also
  // multiplies in what the layers in front let through.
  const shadowState = { passes: 0, passMs: 0, final: true, scale: 1 };   // (scale: the least)
  api.shadows = shadowState;

  // A texture of w × h the GPU draws into (internal format, format, type) → {tex, fb}.
  function drawable(w, h, internal, format, type) {
    const tex = gl.createTexture();
    gl.bindTexture(gl.TEXTURE_2D, tex);
    gl.texImage2D(gl.TEXTURE_2D, 0, internal, w, h, 0, format, type, null);
    unfiltered();
    const fb = gl.createFramebuffer();
    gl.bindFramebuffer(gl.FRAMEBUFFER, fb);
    gl.framebufferTexture2D(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.TEXTURE_2D, tex, 0);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    return { tex, fb };
  }

  // A float (or 8-bit) one-channel render target of w × h → {tex, fb, w, h, float}.
  function target(w, h) {
    const float = !!gl.getExtension("EXT_color_buffer_float");
    return { ...(float ? drawable(w, h, gl.R32F, gl.RED, gl.FLOAT)
      : drawable(w, h, gl.RGBA8, gl.RGBA, gl.UNSIGNED_BYTE)), w, h, float };
  }
  function dropTarget(t) {
    if (t) { gl.deleteFramebuffer(t.fb); gl.deleteTexture(t.tex); }
  }

  // -- a painting: its images, its shaders, its lights' shadow textures ----------------------
  // The page shows one painting, or (a scene of layers, §15) one per layer: `PD` is its data
  // (page.py's page_data), `index` its place in the scene (back first).
  function makePainting(PD, index) {
    const P = { data: PD, index, textures: {}, filterable: {}, units: {}, programs: [],
                codeTextures: {}, shadows: [], through: [], prog: null, progWraps: {},
                progCodes: [], drawing: 0, cells: {} };
    const { textures, filterable, units, programs, codeTextures, shadows } = P;

    // The sRGB codes of a colour image, not decoded: for shaders that mix the codes (made
    // the first time one asks).
    function codeTexture(channel) {
      const tex = PD.textures[channel];
      const source = tex.same_as || channel;
      const moving = PD.frames && PD.frames.textures[source];
      const key = moving ? `${source} ${P.drawing}` : source;     // one per drawing shown
      codeTextures[key] = codeTextures[key] ||
        texture(moving ? moving[P.drawing] : PD.textures[source], true);
      return codeTextures[key];
    }

    // What a shader binds for an image — its codes where it mixes codes (`codes`), else the
    // image — and whether the GPU may filter that texture: {texture, filterable}.
    function boundTexture(channel, codes) {
      return codes.includes(channel) ? codeTexture(channel)
        : { texture: textures[channel], filterable: filterable[channel] };
    }

    // A shader of the current look ('frame', 'shadow_sun', 'shadow_point'), compiled the
    // first time it is used.
    function shaderOf(name) {
      const i = PD.looks[state.look].shaders[name];
      programs[i] = programs[i] || program(specialised(i));
      return programs[i];
    }

    // A shader's source with each `hw_<image>` made a constant: whether the GPU filters that
    // image here (its format filterable in this browser, a wrap of the shader's for it), so
    // the compiler drops the path not taken — software renderers do not skip a branch on a
    // uniform for free.
    function specialised(i) {
      const { wraps, codes } = PD.samplers[i];
      const source = new TextDecoder().decode(inflate(PD.shaders[i]));   // (deflated)
      return source.replace(/uniform int hw_(\w+);/g, (_, channel) => {
        return `const int hw_${channel} = ${usesFilter(wraps, codes, channel) ? 1 : 0};`;
      });
    }

    // Whether a shader's lookups of an image go through the GPU's filter: the shader wraps
    // it (`wraps`) and the texture it binds for it is filterable here. One rule for the
    // constant the shader is compiled with (specialised) and the sampler bound when it draws.
    function usesFilter(wraps, codes, channel) {
      return !!wraps[channel] && boundTexture(channel, codes).filterable;
    }

    P.useShader = function (name) {
      P.prog = shaderOf(name);
      ({ wraps: P.progWraps, codes: P.progCodes } =
        PD.samplers[PD.looks[state.look].shaders[name]]);
      gl.useProgram(P.prog);
    };
    P.useLook = () => P.useShader("frame");

    // A light as this painting sees it (§0 in its own frame): a scene's point light moved
    // into the layer's pixels and measured in its image widths; a sun as it is.
    P.lightVector = function (lt) {
      const v = lightVector(lt);
      if (!PD.place || lt.kind !== "point") return v;
      const [x, y, z] = canvasPoint(v), [cx, cy, px, depth] = PD.place;
      const lx = (x - cx) / px, ly = (y - cy) / px;
      return [(lx - PD.width / 2) / PD.width, (ly - PD.height / 2) / PD.width,
              (z - depth) / px / PD.width];
    };

    // The uniforms of the program in use: the look's parameters, its images, the lights
    // (or, for a shadow pass, light `only` as the shader's one light), where it draws.
    P.setUniforms = function (rect, display, only = null) {
      const loc = (name) => gl.getUniformLocation(P.prog, name);
      const drawn = PD.frames && PD.frames.uniforms ? PD.frames.uniforms[P.drawing] : {};
      for (const [name, value] of Object.entries(PD.looks[state.look].uniforms)) {
        gl.uniform1f(loc(name), name === "p_shadows_steps" ? state.steps
          : name in drawn ? drawn[name] : value);
      }
      for (const [channel, unit] of Object.entries(units)) {
        gl.activeTexture(gl.TEXTURE0 + unit);
        gl.bindTexture(gl.TEXTURE_2D, boundTexture(channel, P.progCodes).texture);
        gl.uniform1i(loc("tex_" + channel), unit);
        gl.bindSampler(unit, samplerFor(P.progWraps[channel] || "EXTEND",
                                        usesFilter(P.progWraps, P.progCodes, channel)));
      }
      (only ? [only] : lights).forEach((lt, i) => {
        gl.uniform3fv(loc(`light${i + 1}_vector`), P.lightVector(lt));
        const k = lt.on ? lt.strength : 0;
        gl.uniform3fv(loc(`light${i + 1}_weight`), lt.colour.map((c) => c * k));
      });
      gl.uniform4f(loc("dp_rect"), ...rect);
      gl.uniform1i(loc("dp_display"), display);
      gl.uniform3fv(loc("dp_backdrop"), BACKDROP);
    };

    P.shadowTarget = function (i, w, h) {
      let t = shadows[i];
      if (t && t.w === w && t.h === h) return t;
      dropTarget(t);
      dropTarget(P.through[i]);
      t = shadows[i] = { ...target(w, h), what: "", scale: 1 };
      P.through[i] = PD.through ? target(w, h) : null;
      textures[`shadow_${i}`] = t.tex;
      filterable[`shadow_${i}`] = !t.float || floatLinear;
      return t;
    };

    // Bring each light's shadow texture up to date (see updateShadows) → [passes drawn,
    // ms of the slowest full-size pass, whether all are final].
    P.updateShadows = function (scale) {
      if (!PD.shadows) return [0, 0, true];
      const look = PD.looks[state.look];
      let drawn = 0, finalMs = 0, final = true;
      lights.forEach((lt, i) => {
        const what = JSON.stringify([look.shaders["shadow_" + lt.kind], look.uniforms,
                                     state.steps, lightVector(lt), lt.size || 0, P.drawing,
                                     (PD.front || []).map((k) => scene.paintings[k].drawing)]);
        const old = shadows[i];
        if (old && old.what === what && (old.scale >= 1 || scale < 1)) {
          final = final && old.scale >= 1;
          return;
        }
        const s = old && old.what === what ? 1 : scale;
        const w = Math.max(1, Math.round(PD.width * s));
        const h = Math.max(1, Math.round(PD.height * s));
        P.useShader("shadow_" + lt.kind);             // (compiled before the clock starts)
        const t = P.shadowTarget(i, w, h);
        const start = performance.now();
        gl.bindFramebuffer(gl.FRAMEBUFFER, t.fb);
        gl.viewport(0, 0, w, h);
        P.setUniforms([0, 0, w, h], 0, lt);
        gl.drawArrays(gl.TRIANGLES, 0, 3);
        if (PD.through) P.drawThrough(i, lt, w, h, s >= 1);
        if (s >= 1) {                      // wait for a full-size pass: its time sets the drafts'
          gl.readPixels(0, 0, 1, 1, gl.RGBA, t.float ? gl.FLOAT : gl.UNSIGNED_BYTE,
                        t.float ? new Float32Array(4) : new Uint8Array(4));
          finalMs = Math.max(finalMs, performance.now() - start);
        }
        Object.assign(shadows[i], { what, scale: s });
        final = final && s >= 1;
        drawn++;
      });
      gl.bindFramebuffer(gl.FRAMEBUFFER, null);
      return [drawn, finalMs, final];
    };

    // §15: light i's own term times what the layers in front let through, drawn into the
    // second target and swapped in (the frame reads `shadow_<i>`). A final pass antialiases
    // the shadows' edges as the core does (dp_layers.glsl: T at the centres into a third
    // target, then refined where it steps); a draft draws T at the centres alone.
    P.drawThrough = function (i, lt, w, h, final) {
      const own = shadows[i], out = P.through[i];
      const antialias = final && DATA.layer_quality.antialias > 1;
      if (antialias && (!P.centres || P.centres.w !== w || P.centres.h !== h)) {
        dropTarget(P.centres);             // (made before the binds: making binds a texture)
        P.centres = target(w, h);
      }
      P.throughProg = P.throughProg || program(new TextDecoder().decode(inflate(PD.through)));
      const prog = P.throughProg;
      gl.useProgram(prog);
      gl.viewport(0, 0, w, h);
      const loc = (name) => gl.getUniformLocation(prog, name);
      let unit = 0;
      const bind = (name, tex, linear) => {
        gl.activeTexture(gl.TEXTURE0 + unit);
        gl.bindTexture(gl.TEXTURE_2D, tex);
        gl.bindSampler(unit, samplerFor("EXTEND", linear && floatLinear));
        gl.uniform1i(loc(name), unit++);
        return unit - 1;
      };
      bind("dp_own", own.tex, true);
      bind("dp_surface", P.surface, true);
      PD.front.forEach((k, j) => {
        const other = scene.paintings[k];
        bind(`dp_occ${j}`, other.occluder, true);
        gl.uniform4fv(loc(`dp_occ_place${j}`), other.data.place);
        gl.uniform4fv(loc(`dp_occ_slab${j}`), other.slab);
      });
      gl.uniform4f(loc("dp_rect"), 0, 0, w, h);
      gl.uniform4fv(loc("dp_recv"), PD.place);
      gl.uniform2f(loc("dp_recv_size"), PD.width, PD.height);
      gl.uniform2f(loc("dp_canvas"), DATA.width, DATA.height);
      const v = lightVector(lt), point = lt.kind === "point";
      gl.uniform4f(loc("dp_light"), ...(point ? canvasPoint(v) : v), point ? 1 : 0);
      const size = lt.size || 0;
      gl.uniform1f(loc("dp_light_size"), point ? size * DATA.width : Math.tan(size / 2));
      gl.uniform1i(loc("dp_disc"), size > 0 ? DATA.layer_quality.disc : 1);
      gl.uniform1i(loc("dp_penumbra"), size > 0 && final ? DATA.layer_quality.penumbra : 0);
      gl.uniform1i(loc("dp_steps"), state.steps);
      gl.uniform1f(loc("dp_spacing"), DATA.layer_quality.spacing);
      gl.uniform1i(loc("dp_antialias"), DATA.layer_quality.antialias);
      gl.uniform1i(loc("dp_edge_points"), DATA.layer_quality.edge_points);
      gl.uniform1f(loc("dp_edge_step"), DATA.layer_quality.edge_step);
      // pass 1 reads no centres: its sampler shows the own term, never the target drawn
      const centreUnit = bind("dp_centre", own.tex, false);
      if (antialias) {
        gl.bindFramebuffer(gl.FRAMEBUFFER, P.centres.fb);
        gl.uniform1i(loc("dp_pass"), 1);
        gl.drawArrays(gl.TRIANGLES, 0, 3);
        gl.activeTexture(gl.TEXTURE0 + centreUnit);
        gl.bindTexture(gl.TEXTURE_2D, P.centres.tex);
      }
      gl.bindFramebuffer(gl.FRAMEBUFFER, out.fb);
      gl.uniform1i(loc("dp_pass"), antialias ? 2 : 0);
      gl.drawArrays(gl.TRIANGLES, 0, 3);
      for (let u = 0; u < unit; u++) gl.bindSampler(u, null);
      // swap: the product is the light's shadow texture now
      [shadows[i].tex, shadows[i].fb, out.tex, out.fb] = [out.tex, out.fb, own.tex, own.fb];
      textures[`shadow_${i}`] = shadows[i].tex;
    };

    // A painting that moves (§16): show drawing `d` — the images that move swapped for that
    // drawing's (each made into a texture the first time it is shown, then kept), and a
    // layer's reads of the shadows between layers with them; the shadows drawn again
    // (their key holds the drawing, and those of the layers in front).
    P.setDrawing = function (d) {
      if (!PD.frames || d === P.drawing) return;
      const cell = (c, cells) => {
        P.cells[c] = P.cells[c] || [];
        P.cells[c][d] = P.cells[c][d] || texture(cells[d]);
        return P.cells[c][d].texture;
      };
      for (const [c, cells] of Object.entries(PD.frames.textures)) {
        for (const [other, tex] of Object.entries(PD.textures)) {
          if (other === c || tex.same_as === c) textures[other] = cell(c, cells);
        }
      }
      if (PD.frames.occluder) P.occluder = cell("occluder", PD.frames.occluder);
      if (PD.frames.surface) P.surface = cell("surface", PD.frames.surface);
      if (PD.frames.slab) P.slab = PD.frames.slab[d];
      P.drawing = d;
    };

    // The painting's textures: its images, (a layer) what the shadows between layers read,
    // and a texture unit for each.
    P.init = function () {
      const names = Object.keys(PD.textures).filter((c) => !PD.textures[c].same_as);
      const made = names.map((c) => texture(PD.textures[c]));
      names.forEach((c, i) => { textures[c] = made[i].texture; filterable[c] = made[i].filterable; });
      let unit = 0;
      for (const [c, tex] of Object.entries(PD.textures)) {
        if (tex.same_as) {
          textures[c] = textures[tex.same_as];
          filterable[c] = filterable[tex.same_as];
        }
        units[c] = unit++;
      }
      if (PD.shadows) {
        lights.forEach((lt, i) => {
          P.shadowTarget(i, PD.width, PD.height);
          units[`shadow_${i}`] = unit++;
        });
      }
      // drawing 0's textures are kept as the first cells of a moving one
      const first = (c, tex) => {
        const made = texture(tex);
        if (PD.frames) P.cells[c] = [made];
        return made.texture;
      };
      if (PD.frames) {
        for (const c of Object.keys(PD.frames.textures)) {
          P.cells[c] = [{ texture: textures[c], filterable: filterable[c] }];
        }
      }
      if (PD.occluder) P.occluder = first("occluder", PD.occluder);
      if (PD.surface) P.surface = first("surface", PD.surface);
      P.slab = PD.slab;
      P.useLook();                  // (compiled knowing which images the GPU may filter)
    };
    return P;
  }

  // A point light's place (image widths from the canvas's centre) in canvas pixels.
  function canvasPoint([x, y, z]) {
    return [x * DATA.width + DATA.width / 2, y * DATA.width + DATA.height / 2, z * DATA.width];
  }

  // The fraction of the painting's pixels a moving light's shadows are drawn at: its pass
  // about half as long as a frame (measured on the last full-size pass of one light), so a
  // dragged light's frame costs about 1.5 still ones; never below 1/8 of the side.
  const DRAFT_PASS_SHARE = 0.5;
  function shadowDraftScale() {
    const budget = DRAFT_PASS_SHARE * Math.max(state.fullFrameMs, 1), pass = shadowState.passMs;
    return pass <= budget ? 1 : Math.max(0.125, Math.sqrt(budget / pass));
  }

  // Bring each light's shadow texture up to date, in every painting: a light that moved (or
  // whose look or K changed) is drawn at `scale` of the painting's pixels; with `scale` 1
  // (final) a light last drawn as a draft is drawn again at full size; the others are kept
  // as they are. → how many passes were drawn.
  function updateShadows(scale) {
    let drawn = 0, finalMs = 0, final = true;
    for (const P of paintings) {
      const [d, ms, f] = P.updateShadows(scale);
      drawn += d;
      finalMs += ms;
      final = final && f;
    }
    shadowState.passes += drawn;
    if (finalMs) shadowState.passMs = finalMs;
    shadowState.final = final;
    shadowState.scale = Math.min(1, ...paintings.flatMap((P) => P.shadows.map((t) => t.scale)));
    return drawn;
  }

  // -- a scene of layers (§15): each layer drawn at its place on the canvas, back to front,
  // into a float framebuffer (premultiplied, linear), then shown over the backdrop. A drag
  // with the view button (or Shift) moves the view: layers in front move more (parallax).
  const scene = DATA.layers ? { paintings: [], view: [0, 0] } : null;
  api.view = () => (scene ? scene.view : null);
  let composite = null;                // {fb, tex, w, h}
  const PRESENT = "#version 300 es\nprecision highp float;\nuniform sampler2D img;\n" +
    "uniform vec3 backdrop;\nout vec4 o;\n" +
    "vec3 enc(vec3 c) { c = clamp(c, 0.0, 1.0); return mix(1.055 * pow(c, vec3(1.0 / 2.4)) - 0.055," +
    " c * 12.92, vec3(lessThanEqual(c, vec3(0.0031308)))); }\n" +
    "uniform vec2 size;\n" +
    "void main() { vec4 c = texelFetch(img, ivec2(gl_FragCoord.xy * size), 0);\n" +
    "  o = vec4(enc(c.rgb + backdrop * (1.0 - clamp(c.a, 0.0, 1.0))), 1.0); }\n";
  let presentProg = null;

  // Float where the browser renders to floats and blends them, else sRGB 8-bit (blended in
  // linear light by the GPU, stored as codes: no banding in the dark).
  function compositeTarget(w, h) {
    if (composite && composite.w === w && composite.h === h) return composite;
    if (composite) { gl.deleteFramebuffer(composite.fb); gl.deleteTexture(composite.tex); }
    const float = !!gl.getExtension("EXT_color_buffer_float") &&
      !!gl.getExtension("EXT_float_blend");
    composite = { ...(float ? drawable(w, h, gl.RGBA32F, gl.RGBA, gl.FLOAT)
      : drawable(w, h, gl.SRGB8_ALPHA8, gl.RGBA, gl.UNSIGNED_BYTE)), w, h };
    return composite;
  }

  // The layers composited into framebuffer `fb` (w × h pixels spanning the canvas), each at
  // its rectangle, shifted by the view for parallax (layers nearer the viewer more).
  function drawLayers(fb, w, h, view = scene.view) {
    gl.bindFramebuffer(gl.FRAMEBUFFER, fb);
    gl.viewport(0, 0, w, h);
    gl.clearColor(0, 0, 0, 0);
    gl.clear(gl.COLOR_BUFFER_BIT);
    gl.enable(gl.BLEND);
    gl.blendFunc(gl.ONE, gl.ONE_MINUS_SRC_ALPHA);
    gl.enable(gl.SCISSOR_TEST);
    const k = w / DATA.width;                      // framebuffer pixels per canvas pixel
    for (const P of scene.paintings) {
      const [cx, cy, px, z] = P.data.place;
      const shift = z / DATA.width;                 // parallax: nearer layers move more
      const rect = [(cx + view[0] * shift * DATA.width) * k, (cy + view[1] * shift * DATA.width) * k,
                    P.data.width * px * k, P.data.height * px * k];
      const x0 = Math.max(0, Math.floor(rect[0])), y0 = Math.max(0, Math.floor(rect[1]));
      gl.scissor(x0, y0, Math.max(0, Math.ceil(rect[0] + rect[2]) - x0),
                 Math.max(0, Math.ceil(rect[1] + rect[3]) - y0));
      P.useLook();
      P.setUniforms(rect, 0);
      gl.drawArrays(gl.TRIANGLES, 0, 3);
    }
    gl.disable(gl.SCISSOR_TEST);
    gl.disable(gl.BLEND);
  }

  // The composite (w × h, linear premultiplied) over the backdrop, sRGB-encoded, on the canvas.
  function present(src, w, h) {
    presentProg = presentProg || program(PRESENT);
    gl.useProgram(presentProg);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.activeTexture(gl.TEXTURE0);
    gl.bindTexture(gl.TEXTURE_2D, src);
    gl.bindSampler(0, null);
    gl.uniform1i(gl.getUniformLocation(presentProg, "img"), 0);
    gl.uniform3fv(gl.getUniformLocation(presentProg, "backdrop"), BACKDROP);
    gl.uniform2f(gl.getUniformLocation(presentProg, "size"), w / canvas.width, h / canvas.height);
    gl.viewport(0, 0, canvas.width, canvas.height);
    gl.drawArrays(gl.TRIANGLES, 0, 3);
  }

  // A full frame at the canvas's size; or, while the light moves and full frames are slower
  // than FRAME_BUDGET_MS (shadows on a slow GPU, software WebGL), a draft at a fraction
  // `scale` of the pixels, stretched onto the canvas: the light keeps up with the hand, and
  // the full frame follows as soon as it stops.
  const FRAME_BUDGET_MS = 33;
  let draft = null;                    // {fb, rb, w, h}

  function draw(scale = 1, shadowScale = 1) {
    updateShadows(shadowScale);
    const w = Math.max(1, Math.round(canvas.width * Math.min(scale, 1)));
    const h = Math.max(1, Math.round(canvas.height * Math.min(scale, 1)));
    if (scene) {
      const target = compositeTarget(w, h);
      drawLayers(target.fb, w, h);
      present(target.tex, w, h);
    } else if (scale >= 1) {
      const P = paintings[0];
      P.useLook();
      gl.bindFramebuffer(gl.FRAMEBUFFER, null);
      gl.viewport(0, 0, canvas.width, canvas.height);
      P.setUniforms([0, 0, canvas.width, canvas.height], 1);
      gl.drawArrays(gl.TRIANGLES, 0, 3);
    } else {
      const P = paintings[0];
      P.useLook();
      if (!draft || draft.w !== w || draft.h !== h) {
        if (draft) { gl.deleteFramebuffer(draft.fb); gl.deleteRenderbuffer(draft.rb); }
        draft = { fb: gl.createFramebuffer(), rb: gl.createRenderbuffer(), w, h };
        gl.bindRenderbuffer(gl.RENDERBUFFER, draft.rb);
        gl.renderbufferStorage(gl.RENDERBUFFER, gl.RGBA8, w, h);
        gl.bindFramebuffer(gl.FRAMEBUFFER, draft.fb);
        gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.RENDERBUFFER, draft.rb);
      }
      gl.bindFramebuffer(gl.FRAMEBUFFER, draft.fb);
      gl.viewport(0, 0, w, h);
      P.setUniforms([0, 0, w, h], 1);
      gl.drawArrays(gl.TRIANGLES, 0, 3);
    }
    if (scale < 1 && !scene) {
      gl.bindFramebuffer(gl.READ_FRAMEBUFFER, draft.fb);
      gl.bindFramebuffer(gl.DRAW_FRAMEBUFFER, null);
      gl.blitFramebuffer(0, 0, w, h, 0, 0, canvas.width, canvas.height, gl.COLOR_BUFFER_BIT,
                         gl.LINEAR);
      gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    }
    api.frames++;
    state.drawScale = scale;
    state.dirty = false;
  }

  // How long a full frame takes here (ms, waited for by reading one pixel back): measured
  // once per canvas size and look.
  function measureFullFrame() {
    const one = new Uint8Array(4);
    updateShadows(1);
    const start = performance.now();
    draw(1);
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, one);
    state.fullFrameMs = performance.now() - start;
  }

  function draftScale() {
    const ms = state.fullFrameMs || 0;
    return ms <= FRAME_BUDGET_MS ? 1 : Math.max(0.25, Math.sqrt(FRAME_BUDGET_MS / ms));
  }

  // The painting's premultiplied linear RGBA at its own size, read from a float framebuffer
  // (for tests: compare with the numpy core) → base64 of little-endian float32, row 0 at the
  // bottom, like the core's arrays. A scene: its composite at the canvas's size, or with
  // `layer` that layer alone at its own size (its shadows from the layers in front too).
  api.renderFloat = function (layer = null) {
    const alone = layer === null ? null : paintings[layer];      // one layer, at its own size
    const w = alone ? alone.data.width : DATA.width, h = alone ? alone.data.height : DATA.height;
    if (!gl.getExtension("EXT_color_buffer_float")) throw new Error("no float framebuffer");
    if (scene && !gl.getExtension("EXT_float_blend")) throw new Error("no float blending");
    const fb = gl.createFramebuffer(), rb = gl.createRenderbuffer();
    gl.bindRenderbuffer(gl.RENDERBUFFER, rb);
    gl.renderbufferStorage(gl.RENDERBUFFER, gl.RGBA32F, w, h);
    gl.bindFramebuffer(gl.FRAMEBUFFER, fb);
    gl.framebufferRenderbuffer(gl.FRAMEBUFFER, gl.COLOR_ATTACHMENT0, gl.RENDERBUFFER, rb);
    updateShadows(1);
    if (scene && !alone) {
      drawLayers(fb, w, h, [0, 0]);
    } else {
      const P = alone || paintings[0];
      gl.bindFramebuffer(gl.FRAMEBUFFER, fb);
      gl.viewport(0, 0, w, h);
      P.useLook();
      P.setUniforms([0, 0, w, h], 0);
      gl.drawArrays(gl.TRIANGLES, 0, 3);
    }
    const px = new Float32Array(w * h * 4);
    gl.readPixels(0, 0, w, h, gl.RGBA, gl.FLOAT, px);
    gl.bindFramebuffer(gl.FRAMEBUFFER, null);
    gl.deleteFramebuffer(fb);
    gl.deleteRenderbuffer(rb);
    state.dirty = true;
    const bytes = new Uint8Array(px.buffer);
    let text = "";
    for (let i = 0; i < bytes.length; i += 0x8000) {
      text += String.fromCharCode.apply(null, bytes.subarray(i, i + 0x8000));
    }
    return btoa(text);
  };

  // Milliseconds per frame over `n` frames drawn as the page draws them, each with the
  // lights where they are at that moment; each frame waits for the GPU by reading one pixel
  // back. mode: 1 (default) full frames of a still light (its shadows drawn once, before);
  // a number < 1, frames at that fraction of the pixels; "draft", the frames the page draws
  // while a light moves (draftScale()); "drag", the key light moved 2° round the painting
  // before each frame, drawn as while it is dragged (its shadows at shadowDraftScale(), the
  // frame at draftScale()); "frames", a painting that moves (§16) shown at its next drawing
  // before each frame, drawn as while its frames play (the same scales as "drag").
  // → {ms, scale, shadowScale, passes drawn}
  api.frameTime = function (n, mode = 1) {
    const one = new Uint8Array(4);
    const drag = mode === "drag", frames = mode === "frames";
    if (frames && !DATA.frames) throw new Error("this painting does not move");
    const s = mode === "draft" || drag || frames ? draftScale() : mode;
    const sh = drag || frames ? shadowDraftScale() : 1;
    const turn = (lt) => {
      const [x, y, h] = lt.place, c = Math.cos(0.035), si = Math.sin(0.035);
      lt.place = [c * x - si * y, si * x + c * y, h];
    };
    draw(s, 1);
    gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, one);
    const passes = shadowState.passes, start = performance.now();
    for (let i = 0; i < n; i++) {
      if (drag && keyLight()) turn(keyLight());
      if (frames) showFrame(Math.floor(state.pageFrame) + 1);
      draw(s, sh);
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, one);
    }
    const ms = (performance.now() - start) / n;
    state.dirty = true;
    return { ms, scale: s, shadowScale: sh, passes: shadowState.passes - passes };
  };

  // The physical floor a benchmark compares the page with (issue 29): what the original
  // research system's shader does per pixel, no shadows — seven hardware-filtered reads (normal,
  // dark, bright, alpha control, reflected and refracted images, the background behind), a
  // light's clamped N·L mixing dark and bright with a falloff, a Phong highlight, reflection and
  // refraction offsets with a three-piece Fresnel blend, the alpha mix and the composite over
  // the background — over the page's own images (used in turn where it has fewer than seven).
  // Milliseconds per frame over `n` frames at the canvas's size, each waited for.
  const FLOOR = "#version 300 es\nprecision highp float;\n" +
    "uniform sampler2D t0, t1, t2, t3, t4, t5;\nuniform vec4 rect;\nuniform vec3 light;\n" +
    "out vec4 o;\n" +
    "vec2 mirror(vec2 c) { vec2 f = fract(c * 0.5) * 2.0; return mix(f, 2.0 - f, step(1.0, f)); }\n" +
    "void main() {\n" +
    "  vec2 uv = (gl_FragCoord.xy - rect.xy) / rect.zw;\n" +
    "  vec4 nm = texture(t0, uv);\n" +
    "  vec3 n = normalize(vec3(0.0, 0.0, 1.0) + normalize(nm.rgb * 2.0 - 1.0));\n" +
    "  vec3 p = vec3(uv - 0.5, 0.0), toL = light - p;\n" +
    "  vec3 l = normalize(toL);\n" +
    "  float t = clamp((dot(n, l) - 0.1) / 0.8, 0.0, 1.0) / (1.0 + 0.5 * length(toL) * 4.0);\n" +
    "  vec4 dark = texture(t1, uv), bright = texture(t2, uv);\n" +
    "  vec4 diffuse = dark * (1.0 - t) + bright * t;\n" +
    "  float spec = pow(max(dot(2.0 * dot(n, l) * n - l, vec3(0.0, 0.0, 1.0)), 0.0), 200.0);\n" +
    "  vec3 alpha = texture(t3, uv).rgb;\n" +
    "  vec3 r = 2.0 * n.z * n - vec3(0.0, 0.0, 1.0);\n" +
    "  vec3 refl = texture(t4, mirror(uv + r.xy / r.z * 0.2)).rgb + spec;\n" +
    "  float c1 = n.z, c2 = sqrt(max(1.0 - 0.5 * (1.0 - c1 * c1), 0.0));\n" +
    "  vec3 f = -0.7 * vec3(0.0, 0.0, 1.0) + (0.7 * c1 - c2) * n;\n" +
    "  vec3 refr = texture(t5, uv + f.xy / f.z * 0.2).rgb;\n" +
    "  float a = c1 > 0.8 ? mix(0.0, 0.1, (c1 - 0.8) / 0.2) : c1 > 0.5 ?\n" +
    "    mix(0.6, 0.0, (c1 - 0.5) / 0.3) : mix(1.0, 0.6, c1 / 0.5);\n" +
    "  vec3 fresnel = refl * a + refr * (1.0 - a);\n" +
    "  float k = diffuse.a * (1.0 - alpha.r * 0.5);\n" +
    "  vec3 colour = fresnel * (1.0 - k) + diffuse.rgb * k;\n" +
    "  vec3 back = texture(t5, uv).rgb;\n" +
    "  o = vec4(back * (1.0 - nm.a) + colour * nm.a, 1.0);\n}\n";

  api.floorTime = function (n) {
    const PD = paintings[0].data, textures = paintings[0].textures;
    const names = Object.keys(PD.textures).filter((c) => !PD.textures[c].same_as &&
                                                           !c.startsWith("shadow_"));
    const floor = program(FLOOR), sampler = gl.createSampler();
    gl.samplerParameteri(sampler, gl.TEXTURE_MIN_FILTER, gl.LINEAR);
    gl.samplerParameteri(sampler, gl.TEXTURE_MAG_FILTER, gl.LINEAR);
    const one = new Uint8Array(4);
    const frame = () => {
      gl.useProgram(floor);
      gl.bindFramebuffer(gl.FRAMEBUFFER, null);
      gl.viewport(0, 0, canvas.width, canvas.height);
      for (let i = 0; i < 6; i++) {
        gl.activeTexture(gl.TEXTURE0 + i);
        gl.bindTexture(gl.TEXTURE_2D, textures[names[i % names.length]]);
        gl.bindSampler(i, sampler);
        gl.uniform1i(gl.getUniformLocation(floor, `t${i}`), i);
      }
      gl.uniform4f(gl.getUniformLocation(floor, "rect"), 0, 0, canvas.width, canvas.height);
      gl.uniform3f(gl.getUniformLocation(floor, "light"), 0.3, 0.4, 0.8);
      gl.drawArrays(gl.TRIANGLES, 0, 3);
      gl.readPixels(0, 0, 1, 1, gl.RGBA, gl.UNSIGNED_BYTE, one);
    };
    frame();
    const start = performance.now();
    for (let i = 0; i < n; i++) frame();
    const ms = (performance.now() - start) / n;
    for (let i = 0; i < 6; i++) gl.bindSampler(i, null);
    gl.deleteSampler(sampler);
    gl.deleteProgram(floor);
    state.dirty = true;
    return { ms };
  };

  // -- layout: the canvas fits the stage (or, embedded, shows one image pixel per CSS pixel) --
  function layout() {
    const dpr = window.devicePixelRatio || 1;
    let cssW = DATA.width, cssH = DATA.height;
    if (!EMBED) {
      const stage = document.getElementById("stage").getBoundingClientRect();
      const fit = Math.min(stage.width / DATA.width, stage.height / DATA.height);
      if (fit > 0 && isFinite(fit)) { cssW = DATA.width * fit; cssH = DATA.height * fit; }
    }
    canvas.style.width = cssW + "px";
    canvas.style.height = cssH + "px";
    canvas.width = Math.max(1, Math.round(cssW * dpr));
    canvas.height = Math.max(1, Math.round(cssH * dpr));
    state.dirty = true;
    state.measure = true;
  }

  // -- interaction ---------------------------------------------------------------------------
  const heightInput = document.getElementById("height");
  const heightValue = document.getElementById("height-value");
  const playButton = document.getElementById("play");

  function keyLight() { return lights[state.key]; }

  function showHeight() {
    const lt = keyLight();
    if (!lt) return;
    const h = lt.place[2];
    heightInput.value = h;
    const elevation = Math.atan2(h, Math.hypot(lt.place[0], lt.place[1])) * 180 / Math.PI;
    heightValue.textContent = `${h.toFixed(2)} widths (${elevation.toFixed(0)}°)`;
  }

  function moved() {
    state.dirty = true;
    state.lastInput = performance.now();
    showHeight();
  }

  function placeAt(clientX, clientY) {
    const lt = keyLight();
    if (!lt) return;
    const r = canvas.getBoundingClientRect();
    const x = (clientX - r.left) / r.width - 0.5;             // image widths from the centre
    const y = (0.5 - (clientY - r.top) / r.height) * DATA.height / DATA.width;
    lt.place = [x, y, lt.place[2]];
    moved();
  }

  function setHeight(h) {
    const lt = keyLight();
    if (!lt) return;
    lt.place = [lt.place[0], lt.place[1], Math.min(2, Math.max(0.02, h))];
    moved();
  }

  // A scene of layers: dragging the view moves each layer by its depth (parallax), from
  // where the drag began; the light stays where it is.
  const dragWhat = document.getElementById("drag-what");
  let viewFrom = null;                 // {x, y, view} at the start of a view drag
  function movesView(e) { return !!scene && (e.shiftKey || dragWhat.value === "view"); }
  function viewAt(clientX, clientY) {
    const r = canvas.getBoundingClientRect();
    scene.view = [viewFrom.view[0] + (clientX - viewFrom.x) / r.width,
                  viewFrom.view[1] - (clientY - viewFrom.y) / r.width];
    state.dirty = true;
    state.lastInput = performance.now();
  }

  let dragging = null;
  canvas.addEventListener("pointerdown", (e) => {
    dragging = e.pointerId;
    canvas.setPointerCapture(e.pointerId);
    setPlaying(false);
    if (movesView(e)) viewFrom = { x: e.clientX, y: e.clientY, view: scene.view };
    else placeAt(e.clientX, e.clientY);
    e.preventDefault();
  });
  canvas.addEventListener("pointermove", (e) => {
    if (dragging !== e.pointerId) return;
    if (viewFrom) viewAt(e.clientX, e.clientY);
    else placeAt(e.clientX, e.clientY);
  });
  for (const end of ["pointerup", "pointercancel"]) {
    canvas.addEventListener(end, (e) => {
      if (dragging === e.pointerId) { dragging = null; viewFrom = null; }
    });
  }
  canvas.addEventListener("wheel", (e) => {
    e.preventDefault();
    const lt = keyLight();
    if (lt) setHeight(lt.place[2] * Math.exp(-e.deltaY * 0.001));
  }, { passive: false });
  heightInput.addEventListener("input", () => setHeight(parseFloat(heightInput.value)));

  function reset() {
    lights.forEach((lt) => { lt.place = placeOf(lt); lt.on = true; });
    if (scene) scene.view = [0, 0];
    document.querySelectorAll("#lights input[type=checkbox]").forEach((box) => { box.checked = true; });
    state.phase = 0;
    state.frame = 0;
    setPlaying(false);
    moved();
  }
  document.getElementById("reset").addEventListener("click", reset);

  function setPlaying(on) {
    state.playing = on && lights.length > 0;
    playButton.textContent = state.playing ? "Pause light" : "Play light";   // (frames: their own)
    playButton.setAttribute("aria-pressed", String(state.playing));
    state.last = null;
  }
  playButton.addEventListener("click", () => setPlaying(!state.playing));

  function nudge(dx, dy) {
    const lt = keyLight();
    if (!lt) return;
    lt.place = [lt.place[0] + dx, lt.place[1] + dy, lt.place[2]];
    moved();
  }
  // Keys act on the painting unless a control has the focus (its own keys win there).
  function onKey(e) {
    const step = e.shiftKey ? 0.1 : 0.02;
    const keys = {
      ArrowLeft: () => nudge(-step, 0), ArrowRight: () => nudge(step, 0),
      ArrowUp: () => nudge(0, step), ArrowDown: () => nudge(0, -step),
      PageUp: () => setHeight(keyLight().place[2] * 1.1),
      PageDown: () => setHeight(keyLight().place[2] / 1.1),
      " ": () => setPlaying(!state.playing), r: reset, R: reset, Home: reset,
    };
    const inControl = ["INPUT", "SELECT", "BUTTON", "TEXTAREA"].includes(e.target.tagName);
    if (!keys[e.key] || inControl || e.ctrlKey || e.metaKey || e.altKey) return;
    if (!keyLight() && keys[e.key] !== reset) return;
    keys[e.key]();
    e.preventDefault();
  }
  window.addEventListener("keydown", onKey);

  function buildControls() {
    const box = document.getElementById("lights");
    lights.forEach((lt, i) => {
      const label = document.createElement("label");
      label.className = "light";
      const on = document.createElement("input");
      on.type = "checkbox";
      on.checked = true;
      on.title = `Switch ${lt.name} on or off`;
      on.addEventListener("change", () => { lt.on = on.checked; state.dirty = true; });
      const key = document.createElement("input");
      key.type = "radio";
      key.name = "key";
      key.checked = i === 0;
      key.title = `Drag moves ${lt.name}`;
      key.setAttribute("aria-label", `Drag moves ${lt.name}`);
      key.addEventListener("change", () => { state.key = i; showHeight(); });
      const swatch = document.createElement("span");
      swatch.className = "swatch";
      const c = lt.colour.map((v) => Math.round(255 * Math.min(1, Math.pow(Math.max(v, 0), 1 / 2.2))));
      swatch.style.background = `rgb(${c.join(",")})`;
      label.append(on, swatch, `${lt.name} (${lt.kind})`, key);
      box.append(label);
    });
    if (!lights.length) {
      box.append("none (the painting shows its dark image)");
      heightInput.disabled = playButton.disabled = true;
      document.getElementById("hint").textContent =
        "This painting has no lights to move: it shows its dark image.";
    }
    const select = document.getElementById("look");
    DATA.looks.forEach((look, i) => {
      const option = new Option(look.name, String(i));
      option.title = look.description;
      select.append(option);
    });
    select.addEventListener("change", () => {
      state.look = parseInt(select.value, 10);
      state.dirty = state.measure = true;
    });
    document.getElementById("look-row").hidden = DATA.looks.length < 2;
    framesRow.hidden = !DATA.frames;
    if (DATA.frames) {
      frameInput.max = String(DATA.frames.sequence.length - 1);
      frameInput.addEventListener("input", () => {
        setFramesPlaying(false);
        showFrame(parseInt(frameInput.value, 10));
      });
      framesButton.addEventListener("click", () => setFramesPlaying(!state.framesPlaying));
      frameValue.textContent = `1 / ${DATA.frames.sequence.length}`;
    }
    document.getElementById("view-row").hidden = !scene;
    document.getElementById("info").textContent = levelInfo();
    document.getElementById("title").textContent = DATA.title || "Dynamic painting";
    document.getElementById("credits").textContent = DATA.credits || "";
    showHeight();
  }

  // -- animation: the recipe's keyframed lights, else a turn of the key light ----------------
  // -- a painting that moves (§16): its frames at their rate, Play/Pause and a slider -------
  const framesRow = document.getElementById("frames-row");
  const frameInput = document.getElementById("frame");
  const frameValue = document.getElementById("frame-value");
  const framesButton = document.getElementById("frames-play");

  function showFrame(i) {
    const seq = DATA.frames.sequence;
    state.pageFrame = ((i % seq.length) + seq.length) % seq.length;
    for (const P of paintings) {             // (a scene: each layer's own drawing of it)
      if (P.data.frames) P.setDrawing(P.data.frames.sequence[Math.floor(state.pageFrame)]);
    }
    frameInput.value = Math.floor(state.pageFrame);
    frameValue.textContent = `${Math.floor(state.pageFrame) + 1} / ${seq.length}`;
    state.dirty = true;
  }

  function setFramesPlaying(on) {
    state.framesPlaying = on;
    framesButton.textContent = on ? "Pause" : "Play";
    framesButton.setAttribute("aria-pressed", String(on));
    state.framesLast = null;
  }

  function advanceFrames(now) {
    if (!DATA.frames || !state.framesPlaying) return;
    const dt = state.framesLast == null ? 0 : (now - state.framesLast) / 1000;
    state.framesLast = now;
    const before = Math.floor(state.pageFrame);
    const next = state.pageFrame + dt * DATA.frames.fps;
    if (Math.floor(next) !== before) showFrame(next);
    else state.pageFrame = next;
  }

  // For tests and embedding pages: show frame i of the loop (0-based), frames paused.
  api.setFrame = function (i) {
    if (!DATA.frames) throw new Error("this painting does not move");
    setFramesPlaying(false);
    showFrame(i);
  };

  function advance(now) {
    advanceFrames(now);
    if (!state.playing) return;
    const dt = state.last == null ? 0 : (now - state.last) / 1000;
    state.last = now;
    const anim = DATA.animation;
    if (anim && anim.frames && anim.frames.length) {
      state.frame = (state.frame + dt * anim.fps) % anim.frames.length;
      anim.frames[Math.floor(state.frame)].forEach((v, i) => {
        if (lights[i]) lights[i].place = placeOf({ kind: lights[i].kind, vector: v });
      });
    } else {
      const lt = keyLight();
      const turn = 2 * Math.PI * dt / DATA.turntable_seconds;
      const [x, y, h] = lt.place, c = Math.cos(turn), s = Math.sin(turn);
      lt.place = [c * x - s * y, s * x + c * y, h];
      state.phase = (state.phase + turn) % (2 * Math.PI);
    }
    moved();
  }

  function loop(now) {
    advance(now);
    const moving = dragging !== null || state.playing || state.framesPlaying ||
      now - state.lastInput < 250;
    const prog = paintings.length && paintings[0].prog;
    if (prog && state.measure) {
      state.measure = false;
      measureFullFrame();
    } else if (prog && state.dirty) {
      draw(moving ? draftScale() : 1, moving ? shadowDraftScale() : 1);
    } else if (prog && !moving && (state.drawScale < 1 || !shadowState.final)) {
      draw(1, 1);                                // the light stopped: the full frame
    }
    requestAnimationFrame(loop);
  }

  function start() {
    if (EMBED) document.documentElement.classList.add("embed");
    buildControls();
    if (!gl) {
      fail("This painting needs WebGL2, which this browser does not offer (or has switched " +
           "off). Try a current Firefox, Chrome, Edge or Safari, with hardware acceleration on.");
      return;
    }
    state.steps = DATA.steps;
    try {
      const layers = scene ? DATA.layers : [DATA];
      layers.forEach((PD, i) => paintings.push(makePainting(PD, i)));
      if (scene) scene.paintings = paintings;
      paintings.forEach((P) => P.init());
    } catch (err) {
      fail(String(err.message || err));
      return;
    }
    canvas.addEventListener("webglcontextlost", (e) => {
      e.preventDefault();
      fail("The graphics card dropped this page's drawing (WebGL context lost): reload the page.");
    });
    layout();
    new ResizeObserver(layout).observe(document.getElementById("stage"));
    window.addEventListener("resize", layout);
    draw();
    document.body.dataset.state = "ready";
    requestAnimationFrame(loop);
  }

  // drawn before the load event (no await on the way); `ready` stays a promise for the tests
  api.ready = new Promise((resolve) => {
    try { start(); } catch (err) { fail(String(err.message || err)); }
    resolve();
  });
})();
