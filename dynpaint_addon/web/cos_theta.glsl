// The cos-θ term (pipeline.md §6) marched in the fragment shader, per pixel and per frame: the
// GLSL twin of shaders_osl/cos_theta.h, itself a port of dynpaint_addon/core/shadow.py (the
// reference; read its comments for the why). Units are pixels inside, like the core.
// DP_NORMAL_DECODE(color, flip, zmin, normal) is defined by the generated shader (the §2
// decode of its graph).

float dp_relief_px(sampler2D relief, float x, float y, float W, float H, float scale)
{
    float a;
    return dp_tex(relief, 0, vec3(x / W, y / H, 0.0), 1, 0, a).x * scale;
}

vec2 dp_slope(sampler2D relief, int srgb, float x, float y, float W, float H, float flip, float zmin)
{
    float a;
    vec3 c = dp_tex(relief, srgb, vec3(x / W, y / H, 0.0), 1, 0, a);
    vec3 n = vec3(0.0, 0.0, 1.0);
    DP_NORMAL_DECODE(c, flip, zmin, n);
    return -n.xy / n.z;
}

bool dp_inside_box(float x, float y, float W, float H)
{
    return x >= 0.5 && x <= W - 0.5 && y >= 0.5 && y <= H - 0.5;
}

// Distance along (lx, ly) until the ray leaves the box of pixel centres (0 outside it).
float dp_exit_distance(float x0, float y0, float lx, float ly, float W, float H)
{
    if (!dp_inside_box(x0, y0, W, H)) return 0.0;
    float big = 1e30;
    float tx = lx > 0.0 ? (W - 0.5 - x0) / lx : (lx < 0.0 ? (0.5 - x0) / lx : big);
    float ty = ly > 0.0 ? (H - 0.5 - y0) / ly : (ly < 0.0 ? (0.5 - y0) / ly : big);
    return max(min(tx, ty), 0.0);
}

float dp_occupancy(float d0, float d1)
{
    float total = abs(d0) + abs(d1);
    return total > 0.0 ? (max(d0, 0.0) + max(d1, 0.0)) / total : 0.0;
}

// t = d / max(r, d) for the surface point at UV (u, v) with unit normal N.
// light: a sun's direction toward the light, or a point light's position (image widths from
// the painting's centre), in the painting frame. relief_max: highest relief (image widths);
// slope_max: steepest implied slope of a normal map.
float dp_cos_theta(vec3 N, vec3 light, bool is_point, float u, float v,
                   sampler2D relief, int relief_srgb, bool normal_map, float flip, float zmin,
                   float W, float H, float height_scale, float offset, float steps,
                   float reach, float relief_max, float slope_max)
{
    const float inf = 1e30;
    float scale = height_scale * W;                          // H (0..1) → pixels
    float x = u * W, y = v * H;
    float zs = normal_map ? 0.0 : dp_relief_px(relief, x, y, W, H, scale);
    float d = max(0.0, offset) * W;
    float x0 = x - d * N.x, y0 = y - d * N.y, z0 = zs - d * N.z;
    vec3 L;
    vec3 pl = vec3(light.x * W + W / 2.0, light.y * W + H / 2.0, light.z * W);
    float dist = 0.0;
    if (is_point) {                       // §6 Which ray: from P0 to the light, ending there
        vec3 to = pl - vec3(x0, y0, z0);
        dist = length(to);
        L = dist > 0.0 ? to / dist : vec3(0.0, 0.0, 1.0);
    } else {
        if (light.z <= 0.0) return 0.0;                     // below the horizon
        L = normalize(light);
    }
    float ndl = dot(N, L);
    float delta, ell_top, h_rec = 0.0;
    if (!normal_map) {
        delta = dp_inside_box(x0, y0, W, H) ? dp_relief_px(relief, x0, y0, W, H, scale) - z0
                                            : d / N.z;
        ell_top = L.z > 0.0 ? (relief_max * W - z0) / L.z : inf;
    } else {
        h_rec = d * (N.x * N.x + N.y * N.y) / N.z;
        delta = h_rec - z0;
        float climb = L.z - slope_max * length(L.xy);
        ell_top = climb > 0.0 ? delta / climb : inf;
    }
    float ell = min(dp_exit_distance(x0, y0, L.x, L.y, W, H), ell_top);
    float ell_light = inf;
    bool stopped = false;
    if (is_point) {
        ell_light = dist;
        stopped = ell_light <= ell;
        ell = min(ell, ell_light);
    }
    // §6 Reach (normal maps): the rebuilt relief is felt up to reach, then the tangent plane
    float reach_px = normal_map ? max(reach, 0.0) * W : inf;
    bool by_reach = ell > reach_px;
    if (by_reach) { ell = reach_px; stopped = false; }
    if (!(ell < inf)) ell = 0.0;
    int k_max = int(max(steps, 0.0));
    int k_eff = k_max > 0 ? min(k_max, max(1, int(ceil(4.0 * ell)))) : 0;
    float inside = 0.0;
    if (k_eff > 0 && ell > 0.0) {
        float a = ell / float(k_eff);
        float ax = a * L.x, ay = a * L.y, az = a * L.z;
        for (int k = 1; k <= k_eff; k++) {
            float px = x0 + float(k) * ax, py = y0 + float(k) * ay;
            float here;
            if (!normal_map) {
                here = dp_relief_px(relief, px, py, W, H, scale);
            } else {
                vec2 g = dp_slope(relief, relief_srgb, px - 0.5 * ax, py - 0.5 * ay, W, H,
                                  flip, zmin);
                h_rec += g.x * ax + g.y * ay;
                here = h_rec;
            }
            float nd = here - (z0 + float(k) * az);
            inside += dp_occupancy(delta, nd) * a;
            delta = nd;
        }
    }
    // tail along the tangent plane of P_S (never past a point light)
    float rate = ndl / N.z;
    float tail = rate > 0.0 ? delta / rate : inf;
    if (!(delta > 0.0)) tail = 0.0;
    if (by_reach) tail = ndl > 0.0 ? max(d / ndl - ell, 0.0) : inf;
    if (is_point) tail = min(tail, ell_light - ell);
    if (stopped) tail = 0.0;
    float r = inside + tail;
    float t;
    if (d > 0.0) t = d / max(r, d);
    else t = r > 1e-3 ? 0.0 : max(ndl, 0.0);
    if (isnan(t)) t = 0.0;
    return clamp(t, 0.0, 1.0);
}
