// Ray-primitive intersection that stays numerically stable. C++ twins: engine/rt/intersect.hpp.

struct Ray {
    vec3 origin;
    vec3 dir;  // not necessarily normalised for triangles; spheres normalise internally
};

// Watertight ray/triangle intersection (Woop, Benthin & Wald 2013, JCGT 2(1)). Shared edges and
// vertices of a closed mesh are hit by exactly one side, so no ray leaks between triangles.
// Returns t in (0, tmax) or -1; bary = (u, v) weights of p1 and p2.
struct WatertightRay {
    vec3 origin;
    ivec3 k;     // kx, ky, kz: kz is the dominant axis of the direction
    vec3 shear;  // Sx, Sy, Sz
};

WatertightRay watertight_setup(Ray ray) {
    WatertightRay w;
    vec3 ad = abs(ray.dir);
    int kz = ad.x > ad.y ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
    int kx = kz == 2 ? 0 : kz + 1;
    int ky = kx == 2 ? 0 : kx + 1;
    if (ray.dir[kz] < 0.0) { int tmp = kx; kx = ky; ky = tmp; }  // keep the winding
    w.k = ivec3(kx, ky, kz);
    w.shear = vec3(ray.dir[kx] / ray.dir[kz], ray.dir[ky] / ray.dir[kz], 1.0 / ray.dir[kz]);
    w.origin = ray.origin;
    return w;
}

float intersect_triangle(WatertightRay w, vec3 p0, vec3 p1, vec3 p2, float tmax, out vec2 bary) {
    bary = vec2(0.0);
    vec3 A = p0 - w.origin, B = p1 - w.origin, C = p2 - w.origin;
    float Ax = A[w.k.x] - w.shear.x * A[w.k.z], Ay = A[w.k.y] - w.shear.y * A[w.k.z];
    float Bx = B[w.k.x] - w.shear.x * B[w.k.z], By = B[w.k.y] - w.shear.y * B[w.k.z];
    float Cx = C[w.k.x] - w.shear.x * C[w.k.z], Cy = C[w.k.y] - w.shear.y * C[w.k.z];
    float U = Cx * By - Cy * Bx;
    float V = Ax * Cy - Ay * Cx;
    float W = Bx * Ay - By * Ax;
    if (U == 0.0 || V == 0.0 || W == 0.0) {
        // On an edge in single precision: decide in double precision (the paper's fallback).
        U = float(double(Cx) * double(By) - double(Cy) * double(Bx));
        V = float(double(Ax) * double(Cy) - double(Ay) * double(Cx));
        W = float(double(Bx) * double(Ay) - double(By) * double(Ax));
    }
    if ((U < 0.0 || V < 0.0 || W < 0.0) && (U > 0.0 || V > 0.0 || W > 0.0)) return -1.0;
    float det = U + V + W;
    if (det == 0.0) return -1.0;
    float Az = w.shear.z * A[w.k.z], Bz = w.shear.z * B[w.k.z], Cz = w.shear.z * C[w.k.z];
    float T = U * Az + V * Bz + W * Cz;
    if (det < 0.0 ? (T >= 0.0 || T < tmax * det) : (T <= 0.0 || T > tmax * det)) return -1.0;
    float inv = 1.0 / det;
    bary = vec2(V * inv, W * inv);
    return T * inv;
}

// Sphere with the numerically robust quadratic of Haines et al., Ray Tracing Gems ch. 7: the
// discriminant from the distance of the closest approach, and the two roots without
// cancellation. Correct for tiny spheres and for spheres far from the origin.
float intersect_sphere(Ray ray, vec3 center, float radius, float tmin, float tmax) {
    float len = length(ray.dir);
    vec3 d = ray.dir / len;
    vec3 f = ray.origin - center;
    float b = -dot(f, d);
    vec3 closest = f + b * d;
    float disc = radius * radius - dot(closest, closest);
    if (disc < 0.0) return -1.0;
    float c = dot(f, f) - radius * radius;
    float q = b + (b >= 0.0 ? 1.0 : -1.0) * sqrt(disc);
    float t0 = q != 0.0 ? c / q : 0.0;
    float t1 = q;
    if (t0 > t1) { float tmp = t0; t0 = t1; t1 = tmp; }
    // t is along the normalised direction; return it along ray.dir.
    if (t0 > tmin * len && t0 < tmax * len) return t0 / len;
    if (t1 > tmin * len && t1 < tmax * len) return t1 / len;
    return -1.0;
}

// Slab test; returns the entry distance (>= 0) or -1 on a miss. (A "large value" for a miss is a
// trap: it compares equal to an unbounded tmax, and every miss then walks the whole tree.)
float intersect_aabb(vec3 bmin, vec3 bmax, vec3 origin, vec3 inv_dir, float tmax) {
    // Near and far planes chosen by the direction's sign (Williams et al. 2005): an empty box
    // (bmin = +inf, bmax = -inf, as the BVH stores empty subtrees) is missed by every ray.
    bvec3 negative = lessThan(inv_dir, vec3(0.0));
    vec3 tn = (mix(bmin, bmax, negative) - origin) * inv_dir;
    vec3 tf = (mix(bmax, bmin, negative) - origin) * inv_dir;
    float enter = max(max(tn.x, tn.y), max(tn.z, 0.0));
    float leave = min(min(tf.x, tf.y), min(tf.z, tmax));
    return enter <= leave ? enter : -1.0;
}

// Moves a secondary ray's origin off the surface along the geometric normal (Wächter & Binder,
// Ray Tracing Gems ch. 6): per coordinate by 16 ulps of itself or by `min_offset`, whichever is
// farther. The tracer passes 2^-19 of the scene's diagonal (rt::ray_offset_for_extent): a hit's
// error grows with the distances in the scene, not with its own coordinates.
vec3 offset_ray(vec3 p, vec3 n, float min_offset) {
    const float int_scale = 16.0;
    ivec3 of_i = ivec3(int_scale * n);
    vec3 p_i = vec3(intBitsToFloat(floatBitsToInt(p.x) + (p.x < 0.0 ? -of_i.x : of_i.x)),
                    intBitsToFloat(floatBitsToInt(p.y) + (p.y < 0.0 ? -of_i.y : of_i.y)),
                    intBitsToFloat(floatBitsToInt(p.z) + (p.z < 0.0 ? -of_i.z : of_i.z)));
    vec3 p_f = p + min_offset * n;
    return mix(p_f, p_i, greaterThan(abs(p_i - p), abs(p_f - p)));
}
