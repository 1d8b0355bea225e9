// Layers that shadow each other, in the web page (pipeline.md §15; the core's reference:
// core/layers.py). One pass per layer and light: the layer's own cos-θ term (`dp_own`, drawn
// by its shadow shader) times T, what the layers in front let through along the ray from each
// pixel's surface point toward the light, marched through each layer in front: the part of
// its slab below its plane (its thickness: its two faces are enough for a card) and the part
// above (its relief: a sample per `dp_spacing` of its pixels, ends included, at most
// `dp_steps`). A light with a size is sampled at `dp_disc` points of its disc (the core's
// sunflower spiral), and again at `dp_penumbra` where those disagree. A final pass
// is drawn twice, as the core's transmittance antialiases: T at the pixels' centres alone
// (dp_pass 1), then (dp_pass 2) T again as the mean over a dp_antialias² grid across each
// pixel where it steps by more than dp_edge_step to a neighbour (each of its rays at its
// share of the light's points, dp_edge_points), times the own term. The
// page's generator writes `dp_front()`, which calls dp_layer once per layer in front
// (samplers are indexed by constants only in GLSL ES 3.00). Distances in canvas pixels, z
// toward the viewer.
precision highp float;
precision highp int;
precision highp sampler2D;

uniform vec4 dp_rect;          // where this pass draws: x, y, width, height (framebuffer px)
uniform sampler2D dp_own;      // the layer's own cos-θ term (§6)
uniform sampler2D dp_surface;  // its surface height P_S.z above its plane, canvas px
uniform vec4 dp_recv;          // the layer on the canvas: corner x, y, px per pixel, depth z
uniform vec2 dp_recv_size;     // its size in its own pixels
uniform vec2 dp_canvas;        // the canvas's size in pixels
uniform vec4 dp_light;         // xyz: a sun's direction, or a point light's canvas position; w: 1 point
uniform float dp_light_size;   // a sun's tan(β/2), a point light's radius (canvas px)
uniform int dp_disc;           // points of the light's disc (1 without a size)
uniform int dp_penumbra;       // points sampled again where dp_disc's disagree (≤ dp_disc: none)
uniform int dp_steps;          // at most this many samples per part of a slab
uniform float dp_spacing;      // samples this many pixels of the crossed layer apart
uniform int dp_pass;           // 0: own × T at the centre; 1: T at the centre; 2: own × T, edges refined
uniform sampler2D dp_centre;   // pass 2: pass 1's T
uniform int dp_antialias;      // pass 2: the grid's side across an edge's pixel
uniform int dp_edge_points;   // pass 2: the light's points each ray of an edge's pixel takes (0: all)
uniform float dp_edge_step;    // pass 2: T's step to a neighbour that makes an edge
out vec4 dp_fragment;

// One layer in front (its image: alpha, relief in canvas px, opacity; place: corner, px, z;
// slab: bottom, top, width, height) → the opacity where the ray first meets its solid, or 0.
float dp_part(sampler2D occ, vec4 place, vec4 slab, vec3 o, vec3 d, float a, float b)
{
    if (b <= a) return -1.0;
    float across = (b - a) * length(d.xy) / place.z;
    int n = int(min(float(max(dp_steps, 2)), max(2.0, ceil(across / dp_spacing) + 1.0)));
    for (int j = 0; j < 4096; j++) {     // n points from end to end (a thin card's faces)
        if (j >= n) break;
        vec3 p = o + (a + (b - a) * (float(j) / float(n - 1))) * d;
        vec2 q = (p.xy - place.xy) / place.z;
        if (q.x < 0.0 || q.y < 0.0 || q.x > slab.z || q.y > slab.w) continue;
        vec4 s = textureLod(occ, q / slab.zw, 0.0);
        if (s.r >= 0.5 && p.z <= place.w + s.g) return s.b;
    }
    return -1.0;
}

float dp_layer(sampler2D occ, vec4 place, vec4 slab, vec3 o, vec3 d, float len)
{
    if (d.z <= 0.0) return 0.0;
    float s0 = max((slab.x - o.z) / d.z, 0.0), s1 = min((slab.y - o.z) / d.z, len);
    if (s1 <= s0) return 0.0;
    float s_plane = clamp((place.w - o.z) / d.z, s0, s1);
    float r = dp_part(occ, place, slab, o, d, s0, s_plane);
    if (r < 0.0) r = dp_part(occ, place, slab, o, d, s_plane, s1);
    return clamp(r, 0.0, 1.0);
}

float dp_front(vec3 o, vec3 d, float len);      // written by the page's generator

// A point of the light's disc: the sunflower spiral of core/layers.disc_points.
vec2 dp_disc_point(int j, int n)
{
    if (n <= 1) return vec2(0.0);
    float k = float(j) + 0.5, r = sqrt(k / float(n)), phi = k * 3.141592653589793 * (3.0 - sqrt(5.0));
    return r * vec2(cos(phi), sin(phi));
}

void dp_basis(vec3 d, out vec3 u, out vec3 v)
{
    vec3 helper = abs(d.z) < 0.9 ? vec3(0.0, 0.0, 1.0) : vec3(1.0, 0.0, 0.0);
    u = normalize(cross(d, helper));
    v = cross(d, u);
}

// The mean of T from o over the points first, first + step, … of the n points of the
// light's disc; mixed: whether they disagreed.
float dp_over_disc(vec3 o, int n, int first, int step, out bool mixed)
{
    vec3 u, v;
    vec3 centre = dp_light.xyz;
    // a point light's disc faces the canvas's centre (core/layers.light_points)
    dp_basis(normalize(dp_light.w > 0.5 ? centre - vec3(0.5 * dp_canvas, 0.0) : centre), u, v);
    float total = 0.0, low = 1.0, high = 0.0;
    int count = 0;
    for (int j = first; j < 256; j += step) {
        if (j >= n) break;
        count++;
        vec2 e = dp_disc_point(j, n);
        vec3 d;
        float len;
        if (dp_light.w > 0.5) {
            vec3 to = centre + dp_light_size * (e.x * u + e.y * v) - o;
            len = length(to);
            d = to / max(len, 1e-12);
        } else {
            d = normalize(normalize(centre) + dp_light_size * (e.x * u + e.y * v));
            len = 1e30;
        }
        float t = dp_front(o, d, len);
        total += t;
        low = min(low, t);
        high = max(high, t);
    }
    mixed = low < high;
    return total / float(max(count, 1));
}

// T at a point of the layer (its own pixels), its rays starting `zs` above its plane: the
// mean over the light's disc, sampled again at dp_penumbra points where dp_disc's disagree
// (core/transmittance's `penumbra`).
float dp_T(vec2 px, float zs)
{
    vec3 o = vec3(dp_recv.xy + dp_recv.z * px, dp_recv.w + zs);
    bool mixed;
    float t = dp_over_disc(o, dp_disc, 0, 1, mixed);
    if (mixed && dp_penumbra > dp_disc && dp_disc > 1)
        t = dp_over_disc(o, dp_penumbra, 0, 1, mixed);
    return t;
}

// T of an edge pixel's antialiasing ray j: at its share of the light's points where
// dp_edge_points asks (every m-th from j mod m of the finer disc: core/transmittance's
// _shared), else dp_T's.
float dp_T_edge(vec2 px, float zs, int j)
{
    int n = dp_penumbra > dp_disc && dp_disc > 1 ? dp_penumbra : dp_disc;
    if (dp_edge_points <= 0 || dp_edge_points >= dp_disc) return dp_T(px, zs);
    vec3 o = vec3(dp_recv.xy + dp_recv.z * px, dp_recv.w + zs);
    int m = max(1, n / dp_edge_points);
    bool mixed;
    return dp_over_disc(o, n, j - (j / m) * m, m, mixed);
}

// Whether pass 1's T steps by more than dp_edge_step from pixel c to a neighbour.
bool dp_on_edge(ivec2 c, float t)
{
    ivec2 last = ivec2(dp_rect.zw) - 1;
    ivec2 beside[4] = ivec2[4](ivec2(1, 0), ivec2(-1, 0), ivec2(0, 1), ivec2(0, -1));
    for (int k = 0; k < 4; k++) {
        ivec2 n = clamp(c + beside[k], ivec2(0), last);
        if (abs(texelFetch(dp_centre, n, 0).r - t) > dp_edge_step) return true;
    }
    return false;
}

void main()
{
    vec2 uv = (gl_FragCoord.xy - dp_rect.xy) / dp_rect.zw;
    vec2 px = uv * dp_recv_size;                                   // the layer's own pixels
    float zs = textureLod(dp_surface, uv, 0.0).r;
    float t;
    if (dp_pass == 2) {
        ivec2 c = ivec2(gl_FragCoord.xy - dp_rect.xy);
        t = texelFetch(dp_centre, c, 0).r;
        if (dp_on_edge(c, t)) {
            vec2 pixel = dp_recv_size / dp_rect.zw;                 // one pass pixel, layer px
            float sum = 0.0;
            for (int j = 0; j < 64; j++) {
                if (j >= dp_antialias * dp_antialias) break;
                vec2 at = (vec2(float(j % dp_antialias), float(j / dp_antialias)) + 0.5)
                          / float(dp_antialias) - 0.5;
                sum += dp_T_edge(px + at * pixel, zs, j);
            }
            t = sum / float(dp_antialias * dp_antialias);
        }
    } else {
        t = dp_T(px, zs);
    }
    float own = dp_pass == 1 ? 1.0 : textureLod(dp_own, uv, 0.0).r;
    dp_fragment = vec4(own * t, 0.0, 0.0, 1.0);
}
