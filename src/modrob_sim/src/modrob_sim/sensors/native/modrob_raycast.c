/* modrob_raycast: batched ray casting against the physics' own ODE geoms (boxes, spheres,
 * capsules, cylinders, planes and the native triangle meshes), for the simulated ray, gpu_ray
 * and Velodyne sensors. Loaded with ctypes (see __init__.py); plain C on Debian's libode-dev.
 *
 * A cast is n rays from one origin: direction i is R * local_dirs[i] (R row-major, the
 * sensor's world rotation). A ray starts at origin + rmin * d and is rmax - rmin long, as
 * Gazebo's ray sensor does; out[i] is the distance from the origin to the closest hit, or
 * INFINITY when nothing is hit. Geoms are culled per call (bounding sphere beyond rmax, or
 * within rmin, where no ray starts) and per ray (the azimuth bin and elevation interval the
 * bounding sphere covers, then a slab test against the geom's AABB, nearest-first with early
 * exit) before ODE's exact ray collider runs, so a world of many objects costs little more than
 * its visible ones. The angles are those of the sensor's frame: a sensor's rays keep theirs from
 * scan to scan, so rc_ray_angles() computes them once (the caller keeps them for rc_prepare()).
 *
 * A cast is rc_prepare() (the culling at this instant), rc_run() (the rays) and rc_release(): a
 * ray sensor prepares in the simulation's thread and may run the rays later in another one, on
 * copies of the geoms (see RcCast), as Gazebo's sensors update in their own thread.
 */
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <ode/ode.h>

typedef struct {
    dGeomID g;
    double lo[3], hi[3];
    int infinite;          /* planes (and anything with an unbounded AABB) */
    int index;             /* caller's index (hit id) */
} RcGeom;

/* distance along the ray where it enters the box, or +inf if it misses within [t0, t1] */
static inline double rc_slab(const double *o, const double *inv, const double *lo, const double *hi,
                             double t0, double t1)
{
    for (int k = 0; k < 3; ++k) {
        double a = (lo[k] - o[k]) * inv[k];
        double b = (hi[k] - o[k]) * inv[k];
        if (a > b) { double t = a; a = b; b = t; }
        if (a != a) a = -INFINITY;   /* 0 * inf when the ray lies in a face plane */
        if (b != b) b = INFINITY;
        if (a > t0) t0 = a;
        if (b < t1) t1 = b;
        if (t0 > t1) return INFINITY;
    }
    return t0;
}

typedef struct { double t; int k; } RcCand;

static int rc_cand_cmp(const void *a, const void *b)
{
    double x = ((const RcCand *)a)->t, y = ((const RcCand *)b)->t;
    return (x > y) - (x < y);
}

#define RC_NAZ 512                /* azimuth bins of the per-scan angular index */

/* The azimuth bin and the elevation (rad) of n directions (need not be unit) in the frame they are
 * given in: rc_prepare's ray_bin and ray_el for its dirs */
void rc_ray_angles(const double *dirs, int n, int *bins, double *els)
{
    for (int i = 0; i < n; ++i) {
        const double *l = dirs + 3 * i;
        double nn = sqrt(l[0] * l[0] + l[1] * l[1] + l[2] * l[2]);
        double z = nn > 0 ? l[2] / nn : 0.0;
        int b = (int)floor((atan2(l[1], l[0]) + M_PI) / (2 * M_PI) * RC_NAZ);
        if (b < 0) b = 0;
        if (b >= RC_NAZ) b = RC_NAZ - 1;
        bins[i] = b;
        els[i] = asin(fmax(-1.0, fmin(1.0, z)));
    }
}

/* One cast prepared at one instant: the geoms in reach with their bounds and the per-scan
 * angular index, and (rc_prepare's `copy`) bodiless copies of the primitive geoms at their poses of
 * that instant, so that rc_run() may run later in another thread while the physics moves the
 * originals. ODE's triangle-mesh, convex and heightfield colliders share caches between threads
 * (Debian's libode lacks ODE_EXT_mt_collisions) and are not copied: a cast with one of them in
 * reach reports `needs_now` and must run at once, in the simulation's thread, on the originals. */
typedef struct {
    int n, m, np_, na, needs_now, copied;
    double origin[3], rot[9], rmin, rmax;
    const double *dirs;
    const int *ray_bin;
    const double *ray_el;
    RcGeom *gs;
    double *el_lo, *el_hi, *pl;
    int *planes, *always, *bin_start, *bin_list;
} RcCast;

void rc_release(RcCast *c)
{
    if (!c) return;
    if (c->copied)
        for (int k = 0; k < c->m; ++k) if (c->gs[k].g) dGeomDestroy(c->gs[k].g);
    free(c->gs); free(c->el_lo); free(c->el_hi); free(c->pl); free(c->planes); free(c->always);
    free(c->bin_start); free(c->bin_list);
    free(c);
}

/* a bodiless copy of a primitive geom at its current world pose, or 0 for a class not copied */
static dGeomID rc_copy(dGeomID g)
{
    dGeomID c = 0;
    dVector3 v;
    switch (dGeomGetClass(g)) {
    case dBoxClass: dGeomBoxGetLengths(g, v); c = dCreateBox(0, v[0], v[1], v[2]); break;
    case dSphereClass: c = dCreateSphere(0, dGeomSphereGetRadius(g)); break;
    case dCapsuleClass: { dReal r, l; dGeomCapsuleGetParams(g, &r, &l); c = dCreateCapsule(0, r, l); break; }
    case dCylinderClass: { dReal r, l; dGeomCylinderGetParams(g, &r, &l); c = dCreateCylinder(0, r, l); break; }
    default: return 0;
    }
    const dReal *p = dGeomGetPosition(g);
    dGeomSetPosition(c, p[0], p[1], p[2]);
    dGeomSetRotation(c, dGeomGetRotation(g));
    return c;
}

/* A cast's first half at this instant. dirs, ray_bin and ray_el (rc_ray_angles() of dirs) are
 * kept by pointer: they must live until rc_run. copy: take copies of the primitives (see RcCast).
 * NULL when out of memory. */
RcCast *rc_prepare(dGeomID *geoms, int ng, const double *origin, const double *rot, const double *dirs,
                   int n, double rmin, double rmax, const int *ray_bin, const double *ray_el, int copy)
{
    RcCast *c = (RcCast *)calloc(1, sizeof(RcCast));
    if (!c) return NULL;
    c->n = n; c->rmin = rmin; c->rmax = rmax;
    c->dirs = dirs; c->ray_bin = ray_bin; c->ray_el = ray_el;
    memcpy(c->origin, origin, sizeof(c->origin));
    memcpy(c->rot, rot, sizeof(c->rot));
    if (n <= 0 || !(rmax > rmin)) return c;
    int cap = ng > 0 ? ng : 1;
    c->gs = (RcGeom *)malloc(sizeof(RcGeom) * cap);
    c->el_lo = (double *)malloc(sizeof(double) * cap);
    c->el_hi = (double *)malloc(sizeof(double) * cap);
    c->planes = (int *)malloc(sizeof(int) * cap);
    c->pl = (double *)malloc(sizeof(double) * 4 * cap);
    c->bin_start = (int *)calloc(RC_NAZ + 1, sizeof(int));
    c->always = (int *)malloc(sizeof(int) * cap);
    int *az0 = (int *)malloc(sizeof(int) * cap), *az1 = (int *)malloc(sizeof(int) * cap);
    if (!c->gs || !c->el_lo || !c->el_hi || !c->planes || !c->pl || !c->bin_start || !c->always || !az0 || !az1) {
        free(az0); free(az1); rc_release(c);
        return NULL;
    }
    RcGeom *gs = c->gs;
    double *el_lo = c->el_lo, *el_hi = c->el_hi, *pl = c->pl;
    int *planes = c->planes, *always = c->always, *bin_start = c->bin_start;
    /* 1. geoms in reach; planes apart (analytic, exact: ODE's plane is n.x = d); for the rest the
     *    azimuth/elevation interval their bounding sphere covers as seen from the origin, in the
     *    sensor's frame (rot's transpose takes the world's to it) */
    int m = 0, np_ = 0, na = 0;
    for (int j = 0; j < ng; ++j) {
        dGeomID g = geoms[j];
        if (!g) continue;
        if (dGeomGetClass(g) == dPlaneClass) {
            dVector4 p;
            dGeomPlaneGetParams(g, p);
            pl[4 * np_] = p[0]; pl[4 * np_ + 1] = p[1]; pl[4 * np_ + 2] = p[2]; pl[4 * np_ + 3] = p[3];
            planes[np_++] = j;
            continue;
        }
        dReal aabb[6];
        dGeomGetAABB(g, aabb);
        RcGeom *r = &gs[m];
        r->g = g;
        r->index = j;
        r->infinite = 0;
        for (int k = 0; k < 3; ++k) {
            r->lo[k] = aabb[2 * k];
            r->hi[k] = aabb[2 * k + 1];
            if (!isfinite(r->lo[k]) || !isfinite(r->hi[k]) || r->hi[k] - r->lo[k] > 1e12) r->infinite = 1;
        }
        if (r->infinite) { always[na++] = m; az0[m] = 1; az1[m] = 0;   /* empty bin range */ ++m; continue; }
        double cw[3], cs[3], c2 = 0, rad2 = 0;
        for (int k = 0; k < 3; ++k) {
            cw[k] = 0.5 * (r->lo[k] + r->hi[k]) - origin[k];
            double h = 0.5 * (r->hi[k] - r->lo[k]);
            c2 += cw[k] * cw[k];
            rad2 += h * h;
        }
        for (int k = 0; k < 3; ++k) cs[k] = rot[k] * cw[0] + rot[3 + k] * cw[1] + rot[6 + k] * cw[2];
        double dist = sqrt(c2), rad = sqrt(rad2) * 1.0001 + 1e-9;
        if (dist - rad > rmax) continue;                    /* out of reach */
        if (dist + rad < rmin) continue;                    /* wholly nearer than where rays start */
        if (dist <= rad * 1.01 + 1e-6) {                    /* origin (nearly) inside */
            always[na++] = m; az0[m] = 1; az1[m] = 0;   /* empty bin range */ ++m; continue;
        }
        double half = asin(rad / dist);
        double el = asin(cs[2] / dist);
        el_lo[m] = el - half;
        el_hi[m] = el + half;
        double horiz = sqrt(cs[0] * cs[0] + cs[1] * cs[1]);
        /* the azimuth half-width grows towards the poles; near them take every bin */
        if (horiz <= rad * 1.01) { az0[m] = 0; az1[m] = RC_NAZ - 1; ++m; continue; }
        double azh = asin(fmin(1.0, rad / horiz));
        double az = atan2(cs[1], cs[0]);
        double b0 = (az - azh + M_PI) / (2 * M_PI) * RC_NAZ, b1 = (az + azh + M_PI) / (2 * M_PI) * RC_NAZ;
        int i0 = (int)floor(b0), i1 = (int)floor(b1);
        if (i1 - i0 >= RC_NAZ - 1) { i0 = 0; i1 = RC_NAZ - 1; }
        az0[m] = i0; az1[m] = i1;
        ++m;
    }
    c->m = m; c->np_ = np_; c->na = na;
    /* 2. bins -> geoms (counting sort) */
    for (int k = 0; k < m; ++k) {
        for (int b = az0[k]; b <= az1[k]; ++b) bin_start[((b % RC_NAZ) + RC_NAZ) % RC_NAZ + 1]++;
    }
    for (int b = 0; b < RC_NAZ; ++b) bin_start[b + 1] += bin_start[b];
    c->bin_list = (int *)malloc(sizeof(int) * (bin_start[RC_NAZ] > 0 ? bin_start[RC_NAZ] : 1));
    int *fill = (int *)malloc(sizeof(int) * RC_NAZ);
    if (!c->bin_list || !fill) { free(fill); free(az0); free(az1); rc_release(c); return NULL; }
    for (int b = 0; b < RC_NAZ; ++b) fill[b] = bin_start[b];
    for (int k = 0; k < m; ++k) {
        for (int b = az0[k]; b <= az1[k]; ++b) { int bb = ((b % RC_NAZ) + RC_NAZ) % RC_NAZ; c->bin_list[fill[bb]++] = k; }
    }
    free(fill); free(az0); free(az1);
    /* 3. the copies (all or none: a cast that needs the originals now uses them for every geom) */
    for (int k = 0; k < m && !c->needs_now; ++k) {
        int cls = dGeomGetClass(gs[k].g);
        if (cls != dBoxClass && cls != dSphereClass && cls != dCapsuleClass && cls != dCylinderClass)
            c->needs_now = 1;
    }
    if (copy && !c->needs_now) {
        for (int k = 0; k < m; ++k) gs[k].g = rc_copy(gs[k].g);
        c->copied = 1;
    }
    return c;
}

/* 1: the cast must run now (in the simulation's thread); 0: it may run later, anywhere */
int rc_needs_now(const RcCast *c) { return c ? (c->needs_now || !c->copied) : 1; }

/* A cast's second half: the rays of a prepared cast. Returns the number of hits. */
int rc_run(const RcCast *c, double *out, int *hit)
{
    int n = c->n;
    double rmin = c->rmin, rmax = c->rmax;
    if (n <= 0) return 0;
    if (!(rmax > rmin)) {
        for (int i = 0; i < n; ++i) { out[i] = INFINITY; if (hit) hit[i] = -1; }
        return 0;
    }
    const double *origin = c->origin, *rot = c->rot, *dirs = c->dirs, *pl = c->pl, *el_lo = c->el_lo,
                 *el_hi = c->el_hi;
    const int *planes = c->planes, *always = c->always, *bin_start = c->bin_start, *bin_list = c->bin_list;
    const RcGeom *gs = c->gs;
    int np_ = c->np_, na = c->na;
    RcCand *cand = (RcCand *)malloc(sizeof(RcCand) * (c->m > 0 ? c->m : 1));
    if (!cand) return -1;
    dGeomID ray = dCreateRay(0, rmax - rmin);
    dGeomRaySetFirstContact(ray, 0);
    dGeomRaySetBackfaceCull(ray, 0);
    dGeomRaySetClosestHit(ray, 1);         /* triangle meshes: the nearest triangle */
    double len = rmax - rmin;
    int nhit = 0;
    for (int i = 0; i < n; ++i) {
        const double *l = dirs + 3 * i;
        double d[3], s[3], inv[3];
        int have_inv = 0;
        for (int k = 0; k < 3; ++k) d[k] = rot[3 * k] * l[0] + rot[3 * k + 1] * l[1] + rot[3 * k + 2] * l[2];
        double nn = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
        if (nn > 0) { d[0] /= nn; d[1] /= nn; d[2] /= nn; }
        for (int k = 0; k < 3; ++k) s[k] = origin[k] + rmin * d[k];
        double best = INFINITY;
        int besti = -1;
        /* planes */
        for (int q = 0; q < np_; ++q) {
            const double *p = pl + 4 * q;
            double den = p[0] * d[0] + p[1] * d[1] + p[2] * d[2];
            if (den == 0) continue;
            double t = (p[3] - (p[0] * s[0] + p[1] * s[1] + p[2] * s[2])) / den;
            if (t >= 0 && t <= len && t < best) { best = t; besti = planes[q]; }
        }
        /* candidates: this ray's azimuth bin, elevation interval, AABB slab; nearest first */
        int nc = 0, bin = c->ray_bin[i];
        double el = c->ray_el[i];
        double lim = best < len ? best : len;
#define RC_INV() do { if (!have_inv) { inv[0] = 1.0 / d[0]; inv[1] = 1.0 / d[1]; inv[2] = 1.0 / d[2]; \
                                       have_inv = 1; } } while (0)
        for (int e = bin_start[bin]; e < bin_start[bin + 1]; ++e) {
            int k = bin_list[e];
            if (el < el_lo[k] || el > el_hi[k]) continue;
            RC_INV();
            double t = rc_slab(s, inv, gs[k].lo, gs[k].hi, 0.0, lim);
            if (t <= lim) { cand[nc].t = t; cand[nc].k = k; ++nc; }
        }
        for (int e = 0; e < na; ++e) {
            int k = always[e];
            if (!gs[k].infinite) RC_INV();
            double t = gs[k].infinite ? 0.0 : rc_slab(s, inv, gs[k].lo, gs[k].hi, 0.0, lim);
            if (t <= lim) { cand[nc].t = t; cand[nc].k = k; ++nc; }
        }
        if (nc > 0) {
            if (nc > 1) qsort(cand, nc, sizeof(RcCand), rc_cand_cmp);
            dGeomRaySet(ray, s[0], s[1], s[2], d[0], d[1], d[2]);
            dGeomRaySetLength(ray, len);
            for (int q = 0; q < nc; ++q) {
                if (cand[q].t > best) break;     /* every later box starts behind the best hit */
                dContactGeom cg;
                int got = dCollide(ray, gs[cand[q].k].g, 1, &cg, sizeof(dContactGeom));
                if (got > 0 && cg.depth >= 0 && cg.depth < best) {
                    best = cg.depth;
                    besti = gs[cand[q].k].index;
                }
            }
        }
        if (besti >= 0) { out[i] = rmin + best; ++nhit; }
        else out[i] = INFINITY;
        if (hit) hit[i] = besti;
    }
#undef RC_INV
    dGeomDestroy(ray);
    free(cand);
    return nhit;
}

/* the world AABB of a geom (for tests and the numpy baseline's culling) */
void rc_geom_aabb(dGeomID g, double *out6)
{
    dReal a[6];
    dGeomGetAABB(g, a);
    for (int k = 0; k < 6; ++k) out6[k] = a[k];
}

/* the SHA-256 of this file as the build saw it (CMakeLists.txt): the loader compares it with the
 * source next to it and refuses a library built from another one */
#ifndef MODROB_SOURCE_SHA256
#define MODROB_SOURCE_SHA256 ""
#endif
const char *modrob_source_sha256(void) { return MODROB_SOURCE_SHA256; }
