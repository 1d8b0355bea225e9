// The cos-θ term (pipeline.md §6) marched in the shader, one shading point at a time: a port
// of dynpaint_addon/core/shadow.py (the reference; read its comments for the why). Exact per
// pixel and per frame, for any light, at render time: no bake.
//
// Shared by the OSL shader (Cycles) and the web page's fragment shader (WebGL2), in the words
// of dp_nodes.h; each language defines DP_IMAGE (an image: a file name, a sampler) and
// dp_image_at(image, mode, u, v) (an image at a UV, linear, edges extended; `mode` is how the
// language reads it: OSL's sRGB flag, GLSL's "the GPU filters it"), and the generated shader
// DP_NORMAL_DECODE(color, flip, zmin, normal) (the §2 decode of its graph).
//
// Units are pixels inside, like the core. The relief is the pre-blurred height image (height
// maps, × h·W), a normal map's integrated relief (image widths), or is rebuilt along the ray
// from the normal map's implied slope −N.xy/N.z (normal maps, which may be non-conservative).

float dp_relief_px(DP_IMAGE relief, int mode, float x, float y, float W, float H, float scale)
{
    vector c = dp_image_at(relief, mode, x / W, y / H);
    return c[0] * scale;
}

vector dp_slope(DP_IMAGE relief, int mode, float x, float y, float W, float H, float flip, float zmin)
{
    vector c = dp_image_at(relief, mode, x / W, y / H);
    vector n = vector(0.0, 0.0, 1.0);
    DP_NORMAL_DECODE(c, flip, zmin, n);
    return vector(-n[0] / n[2], -n[1] / n[2], 0.0);
}

int dp_inside_box(float x, float y, float W, float H)
{
    return (x >= 0.5 && x <= W - 0.5 && y >= 0.5 && y <= H - 0.5) ? 1 : 0;
}

// Distance along (lx, ly) until the ray leaves the box of pixel centres (0 outside it).
float dp_exit_distance(float x0, float y0, float lx, float ly, float W, float H)
{
    if (dp_inside_box(x0, y0, W, H) == 0) return 0.0;
    float big = 1e30;
    float tx = lx > 0.0 ? (W - 0.5 - x0) / lx : (lx < 0.0 ? (0.5 - x0) / lx : big);
    float ty = ly > 0.0 ? (H - 0.5 - y0) / ly : (ly < 0.0 ? (0.5 - y0) / ly : big);
    return max(min(tx, ty), 0.0);
}

float dp_occupancy(float d0, float d1)
{
    float total = fabs(d0) + fabs(d1);
    return total > 0.0 ? (max(d0, 0.0) + max(d1, 0.0)) / total : 0.0;
}

// t = d / max(r, d) for the surface point at UV (u, v) with unit normal N.
// light: a sun's direction toward the light, or a point light's position (image widths from
// the painting's centre), in the painting frame. relief_max: highest relief (image widths);
// slope_max: steepest implied slope of a normal map; reach_limited: 1 where a normal map's
// slopes fit no height field (its relief along the ray stops at reach), 0: the whole ray.
float dp_cos_theta(vector N, vector light, int is_point, float u, float v,
                   DP_IMAGE relief, int relief_mode, int normal_map, float flip, float zmin,
                   float W, float H, float height_scale, float offset, float steps,
                   float reach, float relief_max, float slope_max, float reach_limited)
{
    float scale = height_scale * W;                          // H (0..1) → pixels
    float x = u * W, y = v * H;
    float zs = normal_map != 0 ? 0.0 : dp_relief_px(relief, relief_mode, x, y, W, H, scale);
    float d = max(0.0, offset) * W;
    float x0 = x - d * N[0], y0 = y - d * N[1], z0 = zs - d * N[2];
    vector L = vector(0.0, 0.0, 1.0);
    vector pl = vector(light[0] * W + W / 2.0, light[1] * W + H / 2.0, light[2] * W);
    float dist = 0.0;
    if (is_point != 0) {                  // §6 Which ray: from P0 to the light, ending there
        vector to = pl - vector(x0, y0, z0);
        dist = length(to);
        if (dist > 0.0) L = to / dist;
    } else {
        if (light[2] <= 0.0) return 0.0;                     // below the horizon
        L = normalize(light);
    }
    float ndl = dot(N, L);
    float delta = 0.0, ell_top = 0.0, h_rec = 0.0;
    float inf = 1e30;
    if (normal_map == 0) {
        delta = dp_inside_box(x0, y0, W, H) != 0 ? dp_relief_px(relief, relief_mode, x0, y0, W, H, scale) - z0
                                                 : d / N[2];
        ell_top = L[2] > 0.0 ? (relief_max * W - z0) / L[2] : inf;
    } else {
        h_rec = d * (N[0] * N[0] + N[1] * N[1]) / N[2];
        delta = h_rec - z0;
        float climb = L[2] - slope_max * hypot(L[0], L[1]);
        ell_top = climb > 0.0 ? delta / climb : inf;
    }
    float ell = min(dp_exit_distance(x0, y0, L[0], L[1], W, H), ell_top);
    float ell_light = inf;
    int stopped = 0;
    if (is_point != 0) {
        ell_light = dist;
        stopped = ell_light <= ell ? 1 : 0;
        ell = min(ell, ell_light);
    }
    // §6 Reach (normal maps): the rebuilt relief is felt up to reach, then the tangent plane
    float reach_px = normal_map != 0 && reach_limited > 0.5 ? max(reach, 0.0) * W : inf;
    int by_reach = ell > reach_px ? 1 : 0;
    if (by_reach != 0) { ell = reach_px; stopped = 0; }
    if (!(ell < inf)) ell = 0.0;
    int k_max = int(max(steps, 0.0));
    int k_eff = k_max > 0 ? min(k_max, max(1, int(ceil(4.0 * ell)))) : 0;
    float inside = 0.0;
    if (k_eff > 0 && ell > 0.0) {
        float a = ell / float(k_eff);
        float ax = a * L[0], ay = a * L[1], az = a * L[2];
        for (int k = 1; k <= k_eff; k++) {
            float px = x0 + float(k) * ax, py = y0 + float(k) * ay;
            float here = 0.0;
            if (normal_map == 0) {
                here = dp_relief_px(relief, relief_mode, px, py, W, H, scale);
            } else {
                vector g = dp_slope(relief, relief_mode, px - 0.5 * ax, py - 0.5 * ay, W, H,
                                    flip, zmin);
                h_rec += g[0] * ax + g[1] * ay;
                here = h_rec;
            }
            float nd = here - (z0 + float(k) * az);
            inside += dp_occupancy(delta, nd) * a;
            delta = nd;
        }
    }
    // tail along the tangent plane of P_S (never past a point light)
    float rate = ndl / N[2];
    float tail = rate > 0.0 ? delta / rate : inf;
    if (!(delta > 0.0)) tail = 0.0;
    if (by_reach != 0) tail = ndl > 0.0 ? max(d / ndl - ell, 0.0) : inf;
    if (is_point != 0) tail = min(tail, ell_light - ell);
    if (stopped != 0) tail = 0.0;
    float r = inside + tail;
    float t = 0.0;
    if (d > 0.0) t = d / max(r, d);
    else t = r > 1e-3 ? 0.0 : max(ndl, 0.0);
    if (isnan(t)) t = 0.0;
    return clamp(t, 0.0, 1.0);
}
