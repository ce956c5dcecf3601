/* modrob_ode_native: the per-step hot loop of modrob_sim.physics in C, on the same libode that
 * PyODE uses. Loaded with ctypes (see native.py); every function here mirrors the Python
 * fallback in world.py, which stays the reference for the semantics:
 *   - near callback with Gazebo contact parameters (min mu, kp/kd -> soft ERP/CFM, maxVel and
 *     minDepth emulated on the contact depth, fdir1 of the smaller mu1 not projected, maxContacts), same-model /
 *     adjacent-link filtering, a cap of contacts per pair chosen as spread points, friction
 *     direction along the slip;
 *   - collide + quickStep with a per-world ODE random seed, solved twice when a contact's
 *     correction was capped (Gazebo's split of position and velocity correction);
 *   - the velocity part of the blow-up guard;
 *   - contact watches: the pairs a few watched geoms made contacts in and in how many steps,
 *     between two drains (World.watch_contacts, for Gazebo's <gripper>);
 *   - triangle meshes (PyODE on Debian is built without trimesh support) in spaces of their own;
 *   - the World's actuators and turn counts, stretches of whole steps between Python hooks, link
 *     poses and twists into arrays.
 * No Python API: plain C, so it builds with nothing but libode-dev. Nothing here reads the wall
 * clock or knows a ROS message.
 */
#include <math.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <ode/ode.h>

#define MR_MAX_GEN 64          /* contacts generated per pair before selection */

typedef struct {
    double mu1, mu2, kp, kd, max_vel, min_depth;
    double fdir[3];            /* direction of mu1 in the collision frame */
    int has_fdir;
    int max_contacts;          /* the collision's own cap per pair (<maxContacts>), 0 = none */
} MrSurface;

typedef struct {
    dGeomID geom;              /* key (NULL = empty, (dGeomID)1 = deleted) */
    int model;                 /* compact model index (contact counters) */
    int model_uid;             /* unique model id (same-model test) */
    int group;                 /* body group inside the model */
    int self_collide;
    int surface;
    int nwatch;                /* how many contact watches hold this geom (0: mr_near skips them) */
} MrGeomRec;

typedef struct {
    dGeomID g1, g2;
    double pos[3], normal[3], depth;
    dJointID joint;            /* its contact joint (of this step's group) */
    dJointFeedback fb;         /* what the joint did in the step: force and torque on each body */
} MrContactRec;

/* a contact joint made in this step, kept for the position pass of mr_split_solve */
typedef struct {
    dContact ct;               /* as made: depth capped at the maxVel correction */
    double full_depth;         /* the depth past minDepth, uncapped */
    dBodyID b1, b2;
} MrMade;

/* a pair that made contacts: a watched geom and the geom on a body it touched, and in how many
 * steps since the last drain */
typedef struct {
    dGeomID mine, other;
    int steps;
} MrSeenPair;

/* a contact watch (World.watch_contacts): its geoms, and the pairs seen since it was last drained */
typedef struct {
    int live;
    dGeomID *geoms;
    int ngeoms, capgeoms;
    MrSeenPair *seen;
    int nseen, capseen;
} MrContactWatch;

/* a sticking contact's anchor (mr_anchor): the point of each side (body frame; world frame on a
 * static side) where the contact was when it began */
typedef struct {
    dGeomID g1, g2;
    double a1[3], a2[3];
} MrAnchor;

typedef struct {
    dTriMeshDataID data;
    double *verts;
    int *tris;
    dGeomID geom;
} MrMesh;

typedef struct {
    double aabb[6];
    dGeomID geom;
    dBodyID body;
    int awake;             /* has a body, and it is enabled */
} MrSweepEnt;

typedef struct {
    dWorldID world;
    dSpaceID static_space, dyn_space;     /* PyODE's spaces */
    dSpaceID mesh_static, mesh_dyn;       /* ours, for triangle meshes */
    dJointGroupID contacts;
    /* geom map: open addressing on the pointer */
    MrGeomRec *recs;
    size_t nrec, caprec;
    /* adjacency set of (model_uid, group a, group b) keys */
    uint64_t *adj;
    size_t nadj, capadj;
    MrSurface *surf;
    int nsurf, capsurf;
    int *model_contacts;
    int nmodels;
    MrMesh *meshes;
    int nmesh, capmesh;
    /* the contacts of the last step (for world.contacts()): geom pair, pos, normal, depth */
    MrContactRec *log;
    int nlog, caplog;
    /* the contact joints of this step, and whether one of them was capped (mr_split_solve) */
    MrMade *made;
    int nmade, capmade, capped;
    /* body states saved around the first pass of mr_split_solve: 19 doubles per body */
    double *saved;
    int capsaved;
    /* per-step settings */
    double dt, layer, gravity[3];
    int max_contacts;
    int ncontacts;
    unsigned long seed;        /* this world's ODE random seed */
    /* the broadphase (mr_sweep): the geoms' AABBs, sorted by the lower x bound */
    MrSweepEnt *sweep;
    int capsweep;
    /* the contact watches (slots; a freed one is reused) */
    MrContactWatch *watches;
    int nwatches, capwatches;
    /* the contacts' anchors: the last step's (matched by this step's contacts) and this step's */
    MrAnchor *anc_prev, *anc_cur;
    int nanc_prev, nanc_cur, capanc_prev, capanc_cur;
    /* the last step's anchors by pair (a pair's anchors are consecutive): open addressing on the
     * pair, each slot the index of the pair's first anchor + 1 (0 = empty) */
    int *anc_slots;
    size_t capanc_slots;
    dContactGeom gen[MR_MAX_GEN];
} MrCtx;

/* ---- hashing ------------------------------------------------------------------------------ */
static inline size_t mr_hash_ptr(const void *p, size_t cap)
{
    uint64_t x = (uint64_t)(uintptr_t)p;
    x ^= x >> 33; x *= 0xff51afd7ed558ccdULL; x ^= x >> 33;
    return (size_t)(x & (cap - 1));
}

static inline size_t mr_hash_u64(uint64_t x, size_t cap)
{
    x ^= x >> 31; x *= 0x9e3779b97f4a7c15ULL; x ^= x >> 29;
    return (size_t)(x & (cap - 1));
}

#define MR_DELETED ((dGeomID)(uintptr_t)1)

static inline size_t mr_hash_pair(dGeomID a, dGeomID b, size_t cap)
{
    uint64_t x = (uint64_t)(uintptr_t)a, y = (uint64_t)(uintptr_t)b;
    return mr_hash_u64(x < y ? x * 0x9e3779b97f4a7c15ULL + y : y * 0x9e3779b97f4a7c15ULL + x, cap);
}

static MrGeomRec *mr_find(MrCtx *c, dGeomID g)
{
    size_t i = mr_hash_ptr(g, c->caprec);
    for (;;) {
        MrGeomRec *r = &c->recs[i];
        if (r->geom == g) return r;
        if (r->geom == NULL) return NULL;
        i = (i + 1) & (c->caprec - 1);
    }
}

static void mr_rehash(MrCtx *c, size_t newcap)
{
    MrGeomRec *old = c->recs;
    size_t oldcap = c->caprec, i;
    c->recs = (MrGeomRec *)calloc(newcap, sizeof(MrGeomRec));
    c->caprec = newcap;
    c->nrec = 0;
    for (i = 0; i < oldcap; ++i) {
        if (old[i].geom != NULL && old[i].geom != MR_DELETED) {
            size_t j = mr_hash_ptr(old[i].geom, newcap);
            while (c->recs[j].geom != NULL) j = (j + 1) & (newcap - 1);
            c->recs[j] = old[i];
            c->nrec++;
        }
    }
    free(old);
}

static int mr_adj_has(MrCtx *c, uint64_t key)
{
    size_t i;
    if (c->capadj == 0) return 0;
    i = mr_hash_u64(key, c->capadj);
    for (;;) {
        if (c->adj[i] == key) return 1;
        if (c->adj[i] == 0) return 0;
        i = (i + 1) & (c->capadj - 1);
    }
}

static inline uint64_t mr_adj_key(int model_uid, int a, int b)
{
    /* +1 so that no key is 0 (the empty marker); group -1 (world) maps to 0 */
    return ((uint64_t)(uint32_t)(model_uid + 1) << 40) | ((uint64_t)(uint32_t)(a + 1) << 20) |
           (uint64_t)(uint32_t)(b + 1);
}

/* ---- context ------------------------------------------------------------------------------ */
MrCtx *mr_ctx_new(dWorldID world, dSpaceID static_space, dSpaceID dyn_space)
{
    MrCtx *c = (MrCtx *)calloc(1, sizeof(MrCtx));
    c->world = world;
    c->static_space = static_space;
    c->dyn_space = dyn_space;
    c->mesh_static = dHashSpaceCreate(0);
    c->mesh_dyn = dHashSpaceCreate(0);
    dSpaceSetCleanup(c->mesh_static, 0);
    dSpaceSetCleanup(c->mesh_dyn, 0);
    c->contacts = dJointGroupCreate(0);
    c->caprec = 256;
    c->recs = (MrGeomRec *)calloc(c->caprec, sizeof(MrGeomRec));
    c->max_contacts = 4;
    c->dt = 0.001;
    c->layer = 0.001;
    return c;
}

void mr_mesh_destroy_all(MrCtx *c);
void mr_watch_free(MrCtx *c, int w);

void mr_ctx_free(MrCtx *c)
{
    int w;
    if (!c) return;
    for (w = 0; w < c->nwatches; ++w) mr_watch_free(c, w);
    free(c->watches);
    dJointGroupDestroy(c->contacts);
    mr_mesh_destroy_all(c);
    dSpaceDestroy(c->mesh_static);
    dSpaceDestroy(c->mesh_dyn);
    free(c->recs);
    free(c->adj);
    free(c->surf);
    free(c->model_contacts);
    free(c->meshes);
    free(c->log);
    free(c->sweep);
    free(c->made);
    free(c->saved);
    free(c->anc_prev);
    free(c->anc_cur);
    free(c->anc_slots);
    free(c);
}

void mr_set_geom(MrCtx *c, dGeomID g, int model, int model_uid, int group, int self_collide, int surface)
{
    MrGeomRec *r;
    size_t i;
    if ((c->nrec + 1) * 2 > c->caprec) mr_rehash(c, c->caprec * 2);
    r = mr_find(c, g);
    if (!r) {
        i = mr_hash_ptr(g, c->caprec);
        while (c->recs[i].geom != NULL && c->recs[i].geom != MR_DELETED) i = (i + 1) & (c->caprec - 1);
        r = &c->recs[i];
        r->geom = g;
        r->nwatch = 0;
        c->nrec++;
    }
    r->model = model;
    r->model_uid = model_uid;
    r->group = group;
    r->self_collide = self_collide;
    r->surface = surface;
}

static void mr_watch_forget_geom(MrCtx *c, dGeomID g);

void mr_remove_geom(MrCtx *c, dGeomID g)
{
    MrGeomRec *r = mr_find(c, g);
    if (r) {
        if (c->nwatches) mr_watch_forget_geom(c, g);
        r->geom = MR_DELETED;
        /* rebuild to keep probe chains short and reclaim deleted slots */
        mr_rehash(c, c->caprec);
    }
}

void mr_set_surface(MrCtx *c, int idx, double mu1, double mu2, double kp, double kd, double max_vel,
                    double min_depth, double fx, double fy, double fz, int max_contacts)
{
    if (idx >= c->capsurf) {
        int n = c->capsurf ? c->capsurf : 16;
        while (n <= idx) n *= 2;
        c->surf = (MrSurface *)realloc(c->surf, n * sizeof(MrSurface));
        c->capsurf = n;
    }
    if (idx >= c->nsurf) c->nsurf = idx + 1;
    c->surf[idx].mu1 = mu1; c->surf[idx].mu2 = mu2; c->surf[idx].kp = kp; c->surf[idx].kd = kd;
    c->surf[idx].max_vel = max_vel; c->surf[idx].min_depth = min_depth;
    c->surf[idx].fdir[0] = fx; c->surf[idx].fdir[1] = fy; c->surf[idx].fdir[2] = fz;
    c->surf[idx].has_fdir = (fx * fx + fy * fy + fz * fz) > 1e-12;
    c->surf[idx].max_contacts = max_contacts > 0 ? max_contacts : 0;
}

void mr_clear_adjacency(MrCtx *c)
{
    free(c->adj);
    c->adj = NULL;
    c->nadj = c->capadj = 0;
}

void mr_add_adjacent(MrCtx *c, int model_uid, int a, int b)
{
    uint64_t key = mr_adj_key(model_uid, a, b);
    size_t i;
    if ((c->nadj + 1) * 2 > c->capadj) {
        uint64_t *old = c->adj;
        size_t oldcap = c->capadj, k;
        size_t n = c->capadj ? c->capadj * 2 : 64;
        c->adj = (uint64_t *)calloc(n, sizeof(uint64_t));
        c->capadj = n;
        c->nadj = 0;
        for (k = 0; k < oldcap; ++k) {
            if (old[k]) {
                size_t j = mr_hash_u64(old[k], n);
                while (c->adj[j]) j = (j + 1) & (n - 1);
                c->adj[j] = old[k];
                c->nadj++;
            }
        }
        free(old);
    }
    if (mr_adj_has(c, key)) return;
    i = mr_hash_u64(key, c->capadj);
    while (c->adj[i]) i = (i + 1) & (c->capadj - 1);
    c->adj[i] = key;
    c->nadj++;
}

void mr_set_model_count(MrCtx *c, int n)
{
    free(c->model_contacts);
    c->model_contacts = (int *)calloc(n > 0 ? n : 1, sizeof(int));
    c->nmodels = n;
}

int mr_model_contacts(MrCtx *c, int model)
{
    return (model >= 0 && model < c->nmodels) ? c->model_contacts[model] : 0;
}

int mr_last_contacts(MrCtx *c) { return c->ncontacts; }

/* copy up to `max` logged contacts: geoms (2 per contact) and MR_CONTACT_VALS doubles: pos,
 * normal, depth, then the contact joint's feedback of the step (force and torque on body 1, about
 * its centre of mass, then on body 2; world frame; zero on a side without a body) */
#define MR_CONTACT_VALS 19
int mr_contact_vals(void) { return MR_CONTACT_VALS; }
int mr_contact_log(MrCtx *c, void **geoms, double *vals, int max)
{
    int i, n = c->nlog < max ? c->nlog : max;
    for (i = 0; i < n; ++i) {
        const MrContactRec *r = &c->log[i];
        double *v = &vals[MR_CONTACT_VALS * i];
        geoms[2 * i] = (void *)r->g1;
        geoms[2 * i + 1] = (void *)r->g2;
        memcpy(v, r->pos, 3 * sizeof(double));
        memcpy(v + 3, r->normal, 3 * sizeof(double));
        v[6] = r->depth;
        memset(v + 7, 0, 12 * sizeof(double));
        if (dGeomGetBody(r->g1)) {
            memcpy(v + 7, r->fb.f1, 3 * sizeof(double));
            memcpy(v + 10, r->fb.t1, 3 * sizeof(double));
            if (dGeomGetBody(r->g2)) {
                memcpy(v + 13, r->fb.f2, 3 * sizeof(double));
                memcpy(v + 16, r->fb.t2, 3 * sizeof(double));
            }
        } else if (dGeomGetBody(r->g2)) {
            /* attached as (0, b2): ODE makes the one body its first, so its force is f1 */
            memcpy(v + 13, r->fb.f1, 3 * sizeof(double));
            memcpy(v + 16, r->fb.t1, 3 * sizeof(double));
        }
    }
    return n;
}

/* every contact joint of the step reports its forces into its log record (after collision:
 * the log no longer moves) */
static void mr_contact_feedback(MrCtx *c)
{
    int i;
    for (i = 0; i < c->nlog; ++i) {
        memset(&c->log[i].fb, 0, sizeof(dJointFeedback));
        dJointSetFeedback(c->log[i].joint, &c->log[i].fb);
    }
}

/* ---- contact watches ---------------------------------------------------------------------- */
/* A contact watch keeps, for a few geoms (the gripper links of one model), the pairs (watched
 * geom, other geom on a body) that made contacts since it was last drained, each with the
 * number of steps in which it did: mr_near notes them where it makes the contacts (a pair of
 * geoms comes to it at most once per step), so a check that runs every 0.75 s of simulated time
 * (Gazebo's <gripper>, which counts one contact per pair of collisions per step) sees every
 * step's contacts without Python at every step. A geom's record counts the watches that hold it,
 * so that mr_near looks only at watched geoms. */

/* a new watch (a free slot again when one was freed); returns its index */
int mr_watch_new(MrCtx *c)
{
    int w;
    for (w = 0; w < c->nwatches && c->watches[w].live; ++w) {}
    if (w == c->nwatches) {
        if (c->nwatches == c->capwatches) {
            c->capwatches = c->capwatches ? 2 * c->capwatches : 8;
            c->watches = (MrContactWatch *)realloc(c->watches, c->capwatches * sizeof(MrContactWatch));
        }
        c->nwatches++;
    }
    memset(&c->watches[w], 0, sizeof(MrContactWatch));
    c->watches[w].live = 1;
    return w;
}

/* watch `g` (a registered geom) in watch `w`; 0 when there is no such geom or watch */
int mr_watch_add_geom(MrCtx *c, int w, dGeomID g)
{
    MrGeomRec *r = mr_find(c, g);
    MrContactWatch *cw;
    int i;
    if (!r || w < 0 || w >= c->nwatches || !c->watches[w].live) return 0;
    cw = &c->watches[w];
    for (i = 0; i < cw->ngeoms; ++i)
        if (cw->geoms[i] == g) return 1;
    if (cw->ngeoms == cw->capgeoms) {
        cw->capgeoms = cw->capgeoms ? 2 * cw->capgeoms : 4;
        cw->geoms = (dGeomID *)realloc(cw->geoms, cw->capgeoms * sizeof(dGeomID));
    }
    cw->geoms[cw->ngeoms++] = g;
    r->nwatch++;
    return 1;
}

/* mr_near: `mine` (a watched geom) made contacts with `other` in this step */
static void mr_watch_note(MrCtx *c, dGeomID mine, dGeomID other)
{
    int w, i;
    for (w = 0; w < c->nwatches; ++w) {
        MrContactWatch *cw = &c->watches[w];
        if (!cw->live) continue;
        for (i = 0; i < cw->ngeoms && cw->geoms[i] != mine; ++i) {}
        if (i == cw->ngeoms) continue;
        for (i = 0; i < cw->nseen; ++i)
            if (cw->seen[i].mine == mine && cw->seen[i].other == other) break;
        if (i < cw->nseen) {
            cw->seen[i].steps++;
            continue;
        }
        if (cw->nseen == cw->capseen) {
            cw->capseen = cw->capseen ? 2 * cw->capseen : 8;
            cw->seen = (MrSeenPair *)realloc(cw->seen, cw->capseen * sizeof(MrSeenPair));
        }
        cw->seen[cw->nseen].mine = mine;
        cw->seen[cw->nseen].other = other;
        cw->seen[cw->nseen].steps = 1;
        cw->nseen++;
    }
}

/* the pairs watch `w` has seen since its last drain, in the order first seen: 2 geoms per pair
 * into `out` and the pair's steps into `steps` (room for `max` pairs), then forgotten. Returns
 * how many there are; when that is more than `max` nothing is copied or forgotten (ask again
 * with room for them) */
int mr_watch_drain(MrCtx *c, int w, void **out, int *steps, int max)
{
    MrContactWatch *cw;
    int i, n;
    if (w < 0 || w >= c->nwatches || !c->watches[w].live) return 0;
    cw = &c->watches[w];
    n = cw->nseen;
    if (n > max) return n;
    for (i = 0; i < n; ++i) {
        out[2 * i] = (void *)cw->seen[i].mine;
        out[2 * i + 1] = (void *)cw->seen[i].other;
        steps[i] = cw->seen[i].steps;
    }
    cw->nseen = 0;
    return n;
}

/* end watch `w`: its geoms are watched no more (by it), what it saw is dropped, the slot is free */
void mr_watch_free(MrCtx *c, int w)
{
    MrContactWatch *cw;
    int i;
    if (w < 0 || w >= c->nwatches || !c->watches[w].live) return;
    cw = &c->watches[w];
    for (i = 0; i < cw->ngeoms; ++i) {
        MrGeomRec *r = mr_find(c, cw->geoms[i]);
        if (r && r->nwatch > 0) r->nwatch--;
    }
    free(cw->geoms);
    free(cw->seen);
    memset(cw, 0, sizeof(MrContactWatch));
}

/* a geom leaves the world (mr_remove_geom): no watch holds it or a pair with it any more, so no
 * pointer a drain hands out is a freed geom (or a new one at the same address) */
static void mr_watch_forget_geom(MrCtx *c, dGeomID g)
{
    int w, i, k;
    for (w = 0; w < c->nwatches; ++w) {
        MrContactWatch *cw = &c->watches[w];
        if (!cw->live) continue;
        for (i = k = 0; i < cw->ngeoms; ++i)
            if (cw->geoms[i] != g) cw->geoms[k++] = cw->geoms[i];
        cw->ngeoms = k;
        for (i = k = 0; i < cw->nseen; ++i)
            if (cw->seen[i].mine != g && cw->seen[i].other != g) cw->seen[k++] = cw->seen[i];
        cw->nseen = k;
    }
}

/* ---- contact selection -------------------------------------------------------------------- */
/* choose k of n contacts: the deepest, then repeatedly the one farthest from those chosen */
static int mr_select(const dContactGeom *gen, int n, int k, int *out)
{
    int used[MR_MAX_GEN];
    double dmin[MR_MAX_GEN];
    int i, m, best = 0;
    if (n <= k) {
        for (i = 0; i < n; ++i) out[i] = i;
        return n;
    }
    memset(used, 0, sizeof(used));
    for (i = 1; i < n; ++i) if (gen[i].depth > gen[best].depth) best = i;
    out[0] = best;
    used[best] = 1;
    for (i = 0; i < n; ++i) {
        double dx = gen[i].pos[0] - gen[best].pos[0], dy = gen[i].pos[1] - gen[best].pos[1],
               dz = gen[i].pos[2] - gen[best].pos[2];
        dmin[i] = dx * dx + dy * dy + dz * dz;
    }
    for (m = 1; m < k; ++m) {
        int far = -1;
        double fd = -1.0;
        for (i = 0; i < n; ++i) {
            if (!used[i] && dmin[i] > fd) { fd = dmin[i]; far = i; }
        }
        out[m] = far;
        used[far] = 1;
        for (i = 0; i < n; ++i) {
            double dx = gen[i].pos[0] - gen[far].pos[0], dy = gen[i].pos[1] - gen[far].pos[1],
                   dz = gen[i].pos[2] - gen[far].pos[2];
            double d = dx * dx + dy * dy + dz * dz;
            if (d < dmin[i]) dmin[i] = d;
        }
    }
    return k;
}

/* friction direction: along the relative tangential velocity, or at rest along gravity's
 * tangential part; 0 if neither defines one */
static int mr_fdir(MrCtx *c, dBodyID b1, dBodyID b2, const dReal *pos, const dReal *n, dVector3 out)
{
    dVector3 v1 = {0, 0, 0, 0}, v2 = {0, 0, 0, 0};
    double vx, vy, vz, vn, tx, ty, tz, t2, s;
    if (b1) dBodyGetPointVel(b1, pos[0], pos[1], pos[2], v1);
    if (b2) dBodyGetPointVel(b2, pos[0], pos[1], pos[2], v2);
    vx = v1[0] - v2[0]; vy = v1[1] - v2[1]; vz = v1[2] - v2[2];
    vn = vx * n[0] + vy * n[1] + vz * n[2];
    tx = vx - vn * n[0]; ty = vy - vn * n[1]; tz = vz - vn * n[2];
    t2 = tx * tx + ty * ty + tz * tz;
    if (t2 < 1e-10) {
        const double *g = c->gravity;
        double gn = g[0] * n[0] + g[1] * n[1] + g[2] * n[2];
        tx = g[0] - gn * n[0]; ty = g[1] - gn * n[1]; tz = g[2] - gn * n[2];
        t2 = tx * tx + ty * ty + tz * tz;
        if (t2 < 1e-12 * (g[0] * g[0] + g[1] * g[1] + g[2] * g[2] + 1e-30)) return 0;
    }
    s = 1.0 / sqrt(t2);
    out[0] = tx * s; out[1] = ty * s; out[2] = tz * s;
    return 1;
}

#define MR_FDIR_GIVEN 1   /* a surface's <fdir1>, as Gazebo hands it to ODE */
#define MR_FDIR_SLIP 2    /* ours: along the slip (or gravity's tangential part) at the first contact */

/* the first friction direction of one contact of a pair, from the pair's direction `f` (unit):
 * 0 when ODE's own directions are to be used. Each contact against its OWN normal: the contacts of
 * one pair can face different ways (a mesh in a box touches several faces), and a first direction
 * along a contact's normal makes a second normal row whose friction bound mu*N cancels the first,
 * so the solver's impulses grow without bound (NaN, and ODE aborts the process).
 * Given (Gazebo's rule): not projected on the contact plane (a wheel's fdir1 turns with it, so its
 * first friction row leans into the normal as it rolls); ODE's own directions when it is parallel
 * to the normal, as Gazebo's ODE fork falls back. Slip: projected on the contact's plane (contacts
 * with the first one's normal keep it to the last bit). */
static int mr_contact_fdir(const double *f, int kind, const dReal *n, dReal *out)
{
    double fn = f[0] * n[0] + f[1] * n[1] + f[2] * n[2], t[3], t2;
    if (kind == MR_FDIR_GIVEN) {
        double cx = n[1] * f[2] - n[2] * f[1], cy = n[2] * f[0] - n[0] * f[2], cz = n[0] * f[1] - n[1] * f[0];
        if (!(cx * cx + cy * cy + cz * cz > 1e-12)) return 0;
        out[0] = f[0]; out[1] = f[1]; out[2] = f[2];
        return 1;
    }
    if (fabs(fn) <= 1e-9) {
        out[0] = f[0]; out[1] = f[1]; out[2] = f[2];
        return 1;
    }
    t[0] = f[0] - fn * n[0]; t[1] = f[1] - fn * n[1]; t[2] = f[2] - fn * n[2];
    t2 = t[0] * t[0] + t[1] * t[1] + t[2] * t[2];
    if (!(t2 > 1e-12)) return 0;
    t2 = 1.0 / sqrt(t2);
    out[0] = t[0] * t2; out[1] = t[1] * t2; out[2] = t[2] * t2;
    return 1;
}

static void mr_point_to_body(dBodyID b, const dReal *p, double *out)
{
    dVector3 r;
    if (!b) { out[0] = p[0]; out[1] = p[1]; out[2] = p[2]; return; }
    dBodyGetPosRelPoint(b, p[0], p[1], p[2], r);
    out[0] = r[0]; out[1] = r[1]; out[2] = r[2];
}

static void mr_point_to_world(dBodyID b, const double *a, double *out)
{
    dVector3 r;
    if (!b) { out[0] = a[0]; out[1] = a[1]; out[2] = a[2]; return; }
    dBodyGetRelPointPos(b, a[0], a[1], a[2], r);
    out[0] = r[0]; out[1] = r[1]; out[2] = r[2];
}

/* Static friction anchors. ODE's quickStep stops after a fixed number of iterations, so the
 * friction rows of a held object never quite reach what holding it needs: each step it slips by
 * the solver's residual, and the slips add up (a cube squeezed between the light fingers of
 * franka_description's Panda hand crept 1.4 mm/s along them and dropped out after 10 s; with 200
 * iterations it still crept 0.2 mm/s). Gazebo's ODE fork converges such contacts better (no random
 * row order, under-relaxed friction rows), which Debian's ODE 0.16 has no setting for. So each
 * contact remembers where it began on each of its two bodies; while the two points stay within
 * MR_ANCHOR_RADIUS of each other and of the new contact (across the contact plane), the contact's
 * first friction row, along the gap between them, asks for the relative velocity that closes it
 * in one step at the contact's ERP (ODE's contact motion), as the normal row corrects
 * penetration. The bound mu*N still holds: a contact that must slip, slips, and is anchored anew
 * where it is once the points are apart. A rolling contact moves on both bodies and is anchored
 * anew each step. Not for a surface's <fdir1> (wheels). The anchors live one step: a contact of
 * this step takes over that of the last step's contacts of its pair whose points are nearest.
 * Only between two moving bodies (a held object and its fingers): against a static side (the
 * floor, a table) a contact has ODE's own friction, as on Gazebo. Anchored there, a TurtleBot3
 * burger's box caster (mu 0.1), dragged along the floor, turned the robot 0.027 rad at the start
 * of a straight drive. (Rules that left sliding contacts unanchored instead, by the bodies' speed
 * at the contact or by how far the points came apart in a step, let the Panda's held cube creep
 * out of its fingers again.) */
#define MR_ANCHOR_RADIUS 1e-3

/* the index of the last step's first anchor of the pair (o1, o2) in either order, or -1 */
static int mr_anchors_of(MrCtx *c, dGeomID o1, dGeomID o2)
{
    size_t i;
    if (!c->nanc_prev) return -1;
    for (i = mr_hash_pair(o1, o2, c->capanc_slots); c->anc_slots[i]; i = (i + 1) & (c->capanc_slots - 1)) {
        const MrAnchor *q = &c->anc_prev[c->anc_slots[i] - 1];
        if ((q->g1 == o1 && q->g2 == o2) || (q->g1 == o2 && q->g2 == o1)) return c->anc_slots[i] - 1;
    }
    return -1;
}

/* the last step's anchors (just swapped in) indexed by pair */
static void mr_anchors_index(MrCtx *c)
{
    size_t need = 16, i;
    int k;
    while (need < 2 * (size_t)c->nanc_prev) need *= 2;
    if (need > c->capanc_slots) {
        free(c->anc_slots);
        c->anc_slots = (int *)malloc(need * sizeof(int));
        c->capanc_slots = need;
    }
    memset(c->anc_slots, 0, c->capanc_slots * sizeof(int));
    for (k = 0; k < c->nanc_prev; ++k) {
        const MrAnchor *q = &c->anc_prev[k];
        if (k > 0 && q->g1 == c->anc_prev[k - 1].g1 && q->g2 == c->anc_prev[k - 1].g2) continue;
        for (i = mr_hash_pair(q->g1, q->g2, c->capanc_slots); c->anc_slots[i]; i = (i + 1) & (c->capanc_slots - 1))
            ;
        c->anc_slots[i] = k + 1;
    }
}

static void mr_anchor(MrCtx *c, dGeomID o1, dGeomID o2, dBodyID b1, dBodyID b2, dContact *ct, double erp)
{
    const dReal *p = ct->geom.pos, *n = ct->geom.normal;
    const double r2 = MR_ANCHOR_RADIUS * MR_ANCHOR_RADIUS;
    double w1[3], w2[3], best = r2;
    int i, found = -1, swapped = 0;
    MrAnchor *a;
    int first;
    if (!b1 || !b2) return;     /* against a static side: ODE's own friction */
    first = mr_anchors_of(c, o1, o2);
    for (i = first; first >= 0 && i < c->nanc_prev; ++i) {
        const MrAnchor *q = &c->anc_prev[i];
        double d1[3], d2[3], e[3], dn1, dn2, dne, t1, t2, te;
        int sw;
        if (q->g1 == o1 && q->g2 == o2) sw = 0;
        else if (q->g1 == o2 && q->g2 == o1) sw = 1;
        else break;                    /* the pair's anchors end here */
        mr_point_to_world(b1, sw ? q->a2 : q->a1, w1);
        mr_point_to_world(b2, sw ? q->a1 : q->a2, w2);
        d1[0] = w1[0] - p[0]; d1[1] = w1[1] - p[1]; d1[2] = w1[2] - p[2];
        d2[0] = w2[0] - p[0]; d2[1] = w2[1] - p[1]; d2[2] = w2[2] - p[2];
        e[0] = w1[0] - w2[0]; e[1] = w1[1] - w2[1]; e[2] = w1[2] - w2[2];
        dn1 = d1[0] * n[0] + d1[1] * n[1] + d1[2] * n[2];
        dn2 = d2[0] * n[0] + d2[1] * n[1] + d2[2] * n[2];
        dne = e[0] * n[0] + e[1] * n[1] + e[2] * n[2];
        t1 = d1[0] * d1[0] + d1[1] * d1[1] + d1[2] * d1[2] - dn1 * dn1;
        t2 = d2[0] * d2[0] + d2[1] * d2[1] + d2[2] * d2[2] - dn2 * dn2;
        te = e[0] * e[0] + e[1] * e[1] + e[2] * e[2] - dne * dne;
        if (t1 < best && t2 < best && te < r2) { best = t1 > t2 ? t1 : t2; found = i; swapped = sw; }
    }
    if (c->nanc_cur == c->capanc_cur) {
        c->capanc_cur = c->capanc_cur ? 2 * c->capanc_cur : 64;
        c->anc_cur = (MrAnchor *)realloc(c->anc_cur, c->capanc_cur * sizeof(MrAnchor));
    }
    a = &c->anc_cur[c->nanc_cur++];
    a->g1 = o1;
    a->g2 = o2;
    if (found < 0) {
        mr_point_to_body(b1, p, a->a1);
        mr_point_to_body(b2, p, a->a2);
        return;
    }
    {
        const MrAnchor *q = &c->anc_prev[found];
        memcpy(a->a1, swapped ? q->a2 : q->a1, sizeof(a->a1));
        memcpy(a->a2, swapped ? q->a1 : q->a2, sizeof(a->a2));
    }
    mr_point_to_world(b1, a->a1, w1);
    mr_point_to_world(b2, a->a2, w2);
    {
        /* ODE's first friction row asks (v0 - v1) . fdir1 = motion1 at the contact, body 0 being
         * b1, or b2 when b1 is static. The gap e (body 0's point minus body 1's, across the
         * normal) is closed along itself: fdir1 along e, motion1 = -erp |e| / dt, the second row
         * (normal x fdir1) holding still. (A correction split over the rows of a direction that
         * follows the slip fed back into the slip: a box sliding down a ramp turned aside.) */
        double e[3], en, len, sgn = b1 ? 1.0 : -1.0;
        e[0] = sgn * (w1[0] - w2[0]); e[1] = sgn * (w1[1] - w2[1]); e[2] = sgn * (w1[2] - w2[2]);
        en = e[0] * n[0] + e[1] * n[1] + e[2] * n[2];
        e[0] -= en * n[0]; e[1] -= en * n[1]; e[2] -= en * n[2];
        len = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
        if (!(len > 1e-12)) return;
        ct->fdir1[0] = e[0] / len; ct->fdir1[1] = e[1] / len; ct->fdir1[2] = e[2] / len;
        ct->surface.motion1 = -erp * len / c->dt;
        ct->surface.mode |= dContactFDir1 | dContactMotion1;
    }
}

/* the anchors go (World reset, guard restorations: the bodies were put elsewhere) */
void mr_anchors_forget(MrCtx *c)
{
    c->nanc_prev = 0;
    c->nanc_cur = 0;
}

static void mr_near(void *data, dGeomID o1, dGeomID o2)
{
    MrCtx *c = (MrCtx *)data;
    MrGeomRec *r1, *r2;
    dBodyID b1, b2;
    const MrSurface *s1, *s2;
    int n, k, i, sel[MR_MAX_GEN], isotropic, has_fdir = 0, mode;
    double kp, kd, erp, cfm, mu, mu2, shift, cap, max_vel, d1, d2;
    dVector3 fdir = {0, 0, 0, 0};

    if (dGeomIsSpace(o1) || dGeomIsSpace(o2)) {
        dSpaceCollide2(o1, o2, data, &mr_near);
        return;
    }
    r1 = mr_find(c, o1);
    r2 = mr_find(c, o2);
    if (!r1 || !r2) return;
    if (!dGeomIsEnabled(o1) || !dGeomIsEnabled(o2)) return;   /* Link.set_collides(False) */
    if (r1->model_uid == r2->model_uid) {
        if (!(r1->self_collide || r2->self_collide) || r1->group == r2->group ||
            mr_adj_has(c, mr_adj_key(r1->model_uid, r1->group, r2->group)))
            return;
    }
    b1 = dGeomGetBody(o1);
    b2 = dGeomGetBody(o2);
    if (!b1 && !b2) return;
    if ((!b1 || !dBodyIsEnabled(b1)) && (!b2 || !dBodyIsEnabled(b2))) return;
    n = dCollide(o1, o2, MR_MAX_GEN, c->gen, sizeof(dContactGeom));
    if (n <= 0) return;
    s1 = &c->surf[r1->surface];
    s2 = &c->surf[r2->surface];
    /* the pair's cap: the world's, lowered by either collision's own <maxContacts> (Gazebo) */
    k = c->max_contacts;
    if (s1->max_contacts > 0 && s1->max_contacts < k) k = s1->max_contacts;
    if (s2->max_contacts > 0 && s2->max_contacts < k) k = s2->max_contacts;
    k = mr_select(c->gen, n, k, sel);

    kp = 1.0 / (1.0 / s1->kp + 1.0 / s2->kp);
    kd = s1->kd + s2->kd;
    erp = c->dt * kp / (c->dt * kp + kd);
    cfm = 1.0 / (c->dt * kp + kd);
    mu = s1->mu1 < s2->mu1 ? s1->mu1 : s2->mu1;
    mu2 = s1->mu2 < s2->mu2 ? s1->mu2 : s2->mu2;
    isotropic = (mu == mu2);
    /* maxVel and minDepth are per body in Gazebo (the smaller of the two bodies'): a static side
     * does not count; minDepth replaces the world's contact_surface_layer (ODE's is kept at 0),
     * which stays the minDepth of a surface that gives none (min_depth < 0) */
    d1 = s1->min_depth < 0 ? c->layer : s1->min_depth;
    d2 = s2->min_depth < 0 ? c->layer : s2->min_depth;
    if (!b1) {
        shift = d2; max_vel = s2->max_vel;
    } else if (!b2) {
        shift = d1; max_vel = s1->max_vel;
    } else {
        shift = d1 < d2 ? d1 : d2;
        max_vel = s1->max_vel < s2->max_vel ? s1->max_vel : s2->max_vel;
    }
    cap = erp > 0 ? max_vel * c->dt / erp : INFINITY;
    mode = dContactApprox1_1 | dContactApprox1_2 | dContactSoftERP | dContactSoftCFM;
    if (!isotropic) mode |= dContactMu2;
    if (s1->has_fdir || s2->has_fdir) {
        /* <fdir1> given (in the collision frame of its geom): rotated to the world. Both given:
         * the one of the surface with the smaller mu1 (Gazebo) */
        int use2 = s2->has_fdir && (!s1->has_fdir || s1->mu1 > s2->mu1);
        const MrSurface *sf = use2 ? s2 : s1;
        dGeomID og = use2 ? o2 : o1;
        double fx = sf->fdir[0], fy = sf->fdir[1], fz = sf->fdir[2], fn;
        if (dGeomGetClass(og) != dPlaneClass) {  /* a plane is not placeable: its fdir is in the world */
            const dReal *R = dGeomGetRotation(og);
            fx = R[0] * sf->fdir[0] + R[1] * sf->fdir[1] + R[2] * sf->fdir[2];
            fy = R[4] * sf->fdir[0] + R[5] * sf->fdir[1] + R[6] * sf->fdir[2];
            fz = R[8] * sf->fdir[0] + R[9] * sf->fdir[1] + R[10] * sf->fdir[2];
        }
        fn = fx * fx + fy * fy + fz * fz;
        if (fn > 0) {
            double kf = 1.0 / sqrt(fn);
            fdir[0] = fx * kf; fdir[1] = fy * kf; fdir[2] = fz * kf;
            has_fdir = MR_FDIR_GIVEN;
        }
    } else if (isotropic) {
        const dContactGeom *g0 = &c->gen[sel[0]];
        if (mr_fdir(c, b1, b2, g0->pos, g0->normal, fdir)) has_fdir = MR_FDIR_SLIP;
    }
    for (i = 0; i < k; ++i) {
        dContact ct;
        double d, full;
        dJointID j;
        memset(&ct, 0, sizeof(ct));
        ct.geom = c->gen[sel[i]];
        d = ct.geom.depth - shift;
        if (d < 0) d = 0;
        full = d;
        if (d > cap) { d = cap; c->capped = 1; }
        ct.geom.depth = d;
        ct.surface.mode = mode;
        ct.surface.mu = mu;
        ct.surface.mu2 = mu2;
        ct.surface.soft_erp = erp;
        ct.surface.soft_cfm = cfm;
        if (has_fdir && mr_contact_fdir(fdir, has_fdir, ct.geom.normal, ct.fdir1))
            ct.surface.mode |= dContactFDir1;
        if (has_fdir != MR_FDIR_GIVEN)
            mr_anchor(c, o1, o2, b1, b2, &ct, erp);
        j = dJointCreateContact(c->world, c->contacts, &ct);
        dJointAttach(j, b1, b2);
        if (c->nmade == c->capmade) {
            c->capmade = c->capmade ? c->capmade * 2 : 64;
            c->made = (MrMade *)realloc(c->made, c->capmade * sizeof(MrMade));
        }
        c->made[c->nmade].ct = ct;
        c->made[c->nmade].full_depth = full;
        c->made[c->nmade].b1 = b1;
        c->made[c->nmade].b2 = b2;
        ++c->nmade;
        if (c->nlog == c->caplog) {
            c->caplog = c->caplog ? c->caplog * 2 : 64;
            c->log = (MrContactRec *)realloc(c->log, c->caplog * sizeof(MrContactRec));
        }
        {
            MrContactRec *r = &c->log[c->nlog++];
            const dContactGeom *g = &c->gen[sel[i]];
            r->g1 = o1; r->g2 = o2;
            r->joint = j;
            r->pos[0] = g->pos[0]; r->pos[1] = g->pos[1]; r->pos[2] = g->pos[2];
            r->normal[0] = g->normal[0]; r->normal[1] = g->normal[1]; r->normal[2] = g->normal[2];
            r->depth = g->depth;
        }
    }
    c->ncontacts += k;
    /* the contact watches: a watched geom's pair with a geom on a body (a static side does not
     * count, as Gazebo's gripper drops pairs with a static collision) */
    if (r1->nwatch && b2) mr_watch_note(c, o1, o2);
    if (r2->nwatch && b1) mr_watch_note(c, o2, o1);
    if (r1->model >= 0 && r1->model < c->nmodels) c->model_contacts[r1->model] += k;
    if (r2->model != r1->model && r2->model >= 0 && r2->model < c->nmodels) c->model_contacts[r2->model] += k;
}

static inline int mr_space_nonempty(dSpaceID s) { return dSpaceGetNumGeoms(s) > 0; }

static int mr_sweep_cmp(const void *a, const void *b)
{
    double x = ((const MrSweepEnt *)a)->aabb[0], y = ((const MrSweepEnt *)b)->aabb[0];
    return x < y ? -1 : (x > y ? 1 : 0);
}

/* Collect the enabled geoms of ``space`` into the sweep from entry m on; returns the new count.
 * A space inside the space is one entry, whose pairs mr_near hands to dSpaceCollide2, as
 * dSpaceCollide hands them to it. */
static int mr_sweep_collect(MrCtx *c, dSpaceID space, int m)
{
    int n = dSpaceGetNumGeoms(space), i;
    if (m + n > c->capsweep) {
        c->capsweep = 2 * (m + n);
        c->sweep = (MrSweepEnt *)realloc(c->sweep, c->capsweep * sizeof(MrSweepEnt));
    }
    for (i = 0; i < n; ++i) {
        dGeomID g = dSpaceGetGeom(space, i);
        int is_space = dGeomIsSpace(g);
        if (!dGeomIsEnabled(g)) continue;
        dGeomGetAABB(g, c->sweep[m].aabb);
        c->sweep[m].geom = g;
        c->sweep[m].body = is_space ? NULL : dGeomGetBody(g);
        /* a space's geoms may be awake: mr_near judges each of its pairs */
        c->sweep[m].awake = is_space || (c->sweep[m].body && dBodyIsEnabled(c->sweep[m].body));
        ++m;
    }
    return m;
}

/* The moving geoms against each other and against the static ones, to mr_near: the pairs whose
 * bounding boxes overlap, found by sorting on the lower x bound and sweeping. The same tests as
 * ODE's spaces make before their callback (enabled geoms, not two geoms of one body, the category
 * and collide bits, the boxes overlap), and none of the pairs mr_near drops at once (neither geom
 * on an awake body: two static geoms, static and sleeping, two sleeping), so mr_near makes the
 * same contacts as from dSpaceCollide and dSpaceCollide2, in another order. ODE's hash space
 * inserts every geom into its cells at every step, a heap allocation per cell, and
 * dSpaceCollide2 tests every static geom against every moving one: for the 42 moving and 25
 * static geoms of Bulbs and Slides the sweep takes less than half their time (docs/physics.md,
 * "Speed"). */
static void mr_sweep(MrCtx *c, dSpaceID dyn, dSpaceID fixed)
{
    int m, i, k;
    m = mr_sweep_collect(c, dyn, 0);
    m = mr_sweep_collect(c, fixed, m);
    if (m < 2) return;
    qsort(c->sweep, m, sizeof(MrSweepEnt), mr_sweep_cmp);
    for (i = 0; i < m; ++i) {
        const MrSweepEnt *a = &c->sweep[i];
        unsigned long cat_a = dGeomGetCategoryBits(a->geom), col_a = dGeomGetCollideBits(a->geom);
        for (k = i + 1; k < m; ++k) {
            const MrSweepEnt *b = &c->sweep[k];
            if (b->aabb[0] > a->aabb[1]) break;
            if (!(a->awake || b->awake)) continue;
            if (a->aabb[2] > b->aabb[3] || a->aabb[3] < b->aabb[2] ||
                a->aabb[4] > b->aabb[5] || a->aabb[5] < b->aabb[4])
                continue;
            if (a->body && a->body == b->body) continue;
            if (!((cat_a & dGeomGetCollideBits(b->geom)) || (dGeomGetCategoryBits(b->geom) & col_a)))
                continue;
            mr_near(c, a->geom, b->geom);
        }
    }
}

/* collide everything; returns the number of contact joints made. ``layer``: the world's
 * contact_surface_layer, the minDepth of the surfaces that give none */
int mr_collide(MrCtx *c, double dt, double gx, double gy, double gz, double layer, int max_contacts)
{
    c->dt = dt;
    c->gravity[0] = gx; c->gravity[1] = gy; c->gravity[2] = gz;
    c->layer = layer;
    c->max_contacts = max_contacts < 1 ? 1 : (max_contacts > MR_MAX_GEN ? MR_MAX_GEN : max_contacts);
    c->ncontacts = 0;
    c->nlog = 0;
    c->nmade = 0;
    c->capped = 0;
    {                          /* the last step's anchors are matched by this step's contacts */
        MrAnchor *t = c->anc_prev;
        int ct = c->capanc_prev;
        c->anc_prev = c->anc_cur; c->capanc_prev = c->capanc_cur; c->nanc_prev = c->nanc_cur;
        c->anc_cur = t; c->capanc_cur = ct; c->nanc_cur = 0;
    }
    mr_anchors_index(c);
    if (c->nmodels) memset(c->model_contacts, 0, c->nmodels * sizeof(int));
    dJointGroupEmpty(c->contacts);
    mr_sweep(c, c->dyn_space, c->static_space);
    if (mr_space_nonempty(c->mesh_dyn)) {
        dSpaceCollide(c->mesh_dyn, c, &mr_near);
        if (mr_space_nonempty(c->dyn_space))
            dSpaceCollide2((dGeomID)c->mesh_dyn, (dGeomID)c->dyn_space, c, &mr_near);
        if (mr_space_nonempty(c->static_space))
            dSpaceCollide2((dGeomID)c->mesh_dyn, (dGeomID)c->static_space, c, &mr_near);
        if (mr_space_nonempty(c->mesh_static))
            dSpaceCollide2((dGeomID)c->mesh_static, (dGeomID)c->mesh_dyn, c, &mr_near);
    }
    if (mr_space_nonempty(c->mesh_static) && mr_space_nonempty(c->dyn_space))
        dSpaceCollide2((dGeomID)c->mesh_static, (dGeomID)c->dyn_space, c, &mr_near);
    mr_contact_feedback(c);
    return c->ncontacts;
}

int mr_check_bodies(dBodyID *bodies, int start, int n, double vmax2, double wmax2);

/* quickStep with this world's own random seed (quickStep reorders constraints randomly) */
unsigned long mr_quickstep(dWorldID w, double dt, unsigned long seed)
{
    dRandSetSeed(seed);
    dWorldQuickStep(w, dt);
    return dRandGetSeed();
}

void mr_set_seed(MrCtx *c, unsigned long seed) { c->seed = seed; }
unsigned long mr_get_seed(MrCtx *c) { return c->seed; }

/* After a step: a body that may sleep (auto-disable on) and touches an awake body that never
 * sleeps (a robot's link, auto-disable off) has its idle count reset (dBodyEnable). ODE counts a
 * body idle while something holds it still; once the count has run out, each step disables it
 * first and then wakes it again for its island, by the disabled flag alone, so the count stays run
 * out: a bulb held still by a gripper for 0.2 s fell asleep in the step the fingers let go, and
 * stayed where they left it, on a slope it should have slid down. */
static void mr_wake_held(MrCtx *c)
{
    int i;
    for (i = 0; i < c->nlog; ++i) {
        dBodyID b1 = dGeomGetBody(c->log[i].g1), b2 = dGeomGetBody(c->log[i].g2);
        if (!b1 || !b2) continue;
        if (dBodyGetAutoDisableFlag(b1)) {
            if (dBodyIsEnabled(b2) && !dBodyGetAutoDisableFlag(b2)) dBodyEnable(b1);
        } else if (dBodyGetAutoDisableFlag(b2) && dBodyIsEnabled(b1)) {
            dBodyEnable(b2);
        }
    }
}

/* collide + quickStep (with this world's seed) in one call; returns the number of contacts */
int mr_step(MrCtx *c, double dt, double gx, double gy, double gz, double layer, int max_contacts)
{
    int n = mr_collide(c, dt, gx, gy, gz, layer, max_contacts);
    c->seed = mr_quickstep(c->world, dt, c->seed);
    mr_wake_held(c);
    return n;
}

/* Gazebo's split of contact correction (its ODE fork's quickstep: rhs and rhs_erp): the bodies
 * MOVE as if every contact corrected its whole penetration at the contact's ERP, but keep only the
 * velocities of the solve in which the correction is capped at maxVel. Vanilla ODE has one solve;
 * so when a contact of this step was capped (a spawn overlap, a hard impact; never a resting
 * contact below maxVel), the step is solved twice from the same state: first with the capped
 * contacts as made (their velocities are kept), then, from the restored state, with the whole
 * depths (its positions are kept). `bodies` are all bodies that can move (the guard's list). ODE's
 * auto-disable counters see both solves. */
static void mr_split_solve(MrCtx *c, double dt, dBodyID *bodies, int nbodies)
{
    unsigned long seed0 = c->seed;
    int i;
    double *s;
    if (19 * nbodies > c->capsaved) {
        c->capsaved = 19 * nbodies;
        c->saved = (double *)realloc(c->saved, (size_t)c->capsaved * sizeof(double));
    }
    for (i = 0, s = c->saved; i < nbodies; ++i, s += 19) {
        dBodyID b = bodies[i];
        memcpy(s, dBodyGetPosition(b), 3 * sizeof(double));
        memcpy(s + 3, dBodyGetQuaternion(b), 4 * sizeof(double));
        memcpy(s + 7, dBodyGetLinearVel(b), 3 * sizeof(double));
        memcpy(s + 10, dBodyGetAngularVel(b), 3 * sizeof(double));
        memcpy(s + 13, dBodyGetForce(b), 3 * sizeof(double));
        memcpy(s + 16, dBodyGetTorque(b), 3 * sizeof(double));
    }
    mr_quickstep(c->world, dt, seed0);               /* pass 1: the capped correction */
    for (i = 0, s = c->saved; i < nbodies; ++i, s += 19) {
        dBodyID b = bodies[i];
        double v[6];
        memcpy(v, dBodyGetLinearVel(b), 3 * sizeof(double));
        memcpy(v + 3, dBodyGetAngularVel(b), 3 * sizeof(double));
        dBodySetPosition(b, s[0], s[1], s[2]);
        dBodySetQuaternion(b, s + 3);
        dBodySetLinearVel(b, s[7], s[8], s[9]);
        dBodySetAngularVel(b, s[10], s[11], s[12]);
        dBodySetForce(b, s[13], s[14], s[15]);
        dBodySetTorque(b, s[16], s[17], s[18]);
        memcpy(s + 7, v, 6 * sizeof(double));         /* keep pass 1's velocities */
    }
    dJointGroupEmpty(c->contacts);
    for (i = 0; i < c->nmade; ++i) {
        MrMade *m = &c->made[i];
        dJointID j;
        m->ct.geom.depth = m->full_depth;
        j = dJointCreateContact(c->world, c->contacts, &m->ct);
        dJointAttach(j, m->b1, m->b2);
        c->log[i].joint = j;           /* made and log grow together: the same contact */
    }
    mr_contact_feedback(c);
    c->seed = mr_quickstep(c->world, dt, seed0);     /* pass 2: the whole correction */
    for (i = 0, s = c->saved; i < nbodies; ++i, s += 19) {
        dBodySetLinearVel(bodies[i], s[7], s[8], s[9]);
        dBodySetAngularVel(bodies[i], s[10], s[11], s[12]);
    }
}

/* one step with nothing but plain numbers crossing from Python: collide, then ODE's quickStep
 * (world_step 0, Gazebo's "quick") or its exact dWorldStep (1, Gazebo's "world") with this
 * world's seed, then the velocity part of the blow-up guard over `bodies`: *first_bad is the
 * index of the first runaway body (as mr_check_bodies from 0) or -1. Returns the contact count. */
int mr_step_checked(MrCtx *c, double dt, double gx, double gy, double gz, double layer, int max_contacts,
                    int world_step, dBodyID *bodies, int nbodies, double vmax2, double wmax2, int *first_bad)
{
    int n = mr_collide(c, dt, gx, gy, gz, layer, max_contacts);
    if (world_step) {
        dRandSetSeed(c->seed);
        dWorldStep(c->world, dt);
        c->seed = dRandGetSeed();
    } else if (c->capped && nbodies > 0) {
        mr_split_solve(c, dt, bodies, nbodies);
    } else {
        c->seed = mr_quickstep(c->world, dt, c->seed);
    }
    mr_wake_held(c);
    *first_bad = nbodies > 0 ? mr_check_bodies(bodies, 0, nbodies, vmax2, wmax2) : -1;
    return n;
}

/* the largest per-model contact count of the last step, and which model (compact index) */
int mr_max_model_contacts(MrCtx *c, int *which)
{
    int i, best = 0, bi = -1;
    for (i = 0; i < c->nmodels; ++i)
        if (c->model_contacts[i] > best) { best = c->model_contacts[i]; bi = i; }
    *which = bi;
    return best;
}

/* blow-up guard, velocity part: the index of the first body (from `start`) whose linear speed^2
 * or angular speed^2 is not below the limits (NaN fails too), or -1 */
int mr_check_bodies(dBodyID *bodies, int start, int n, double vmax2, double wmax2)
{
    int i;
    for (i = start; i < n; ++i) {
        const dReal *v = dBodyGetLinearVel(bodies[i]);
        const dReal *w = dBodyGetAngularVel(bodies[i]);
        double v2 = v[0] * v[0] + v[1] * v[1] + v[2] * v[2];
        double w2 = w[0] * w[0] + w[1] * w[1] + w[2] * w[2];
        if (!(v2 < vmax2 && w2 < wmax2)) return i;
    }
    return -1;
}

/* explicit joint damping: torque/force -d*v on hinges (kind 0) and sliders (kind 1) */
void mr_apply_damping(dJointID *joints, const int *kinds, const double *coef, int n)
{
    int i;
    for (i = 0; i < n; ++i) {
        if (kinds[i] == 0)
            dJointAddHingeTorque(joints[i], -coef[i] * dJointGetHingeAngleRate(joints[i]));
        else
            dJointAddSliderForce(joints[i], -coef[i] * dJointGetSliderPositionRate(joints[i]));
    }
}

/* ---- triangle meshes ---------------------------------------------------------------------- */
/* verts: nv*3 doubles, tris: nt*3 ints (copied); is_dynamic picks the space */
dGeomID mr_mesh_create(MrCtx *c, const double *verts, int nv, const int *tris, int nt, int is_dynamic)
{
    MrMesh *m;
    if (c->nmesh == c->capmesh) {
        c->capmesh = c->capmesh ? c->capmesh * 2 : 16;
        c->meshes = (MrMesh *)realloc(c->meshes, c->capmesh * sizeof(MrMesh));
    }
    m = &c->meshes[c->nmesh++];
    m->verts = (double *)malloc(sizeof(double) * 3 * (size_t)nv);
    m->tris = (int *)malloc(sizeof(int) * 3 * (size_t)nt);
    memcpy(m->verts, verts, sizeof(double) * 3 * (size_t)nv);
    memcpy(m->tris, tris, sizeof(int) * 3 * (size_t)nt);
    m->data = dGeomTriMeshDataCreate();
    dGeomTriMeshDataBuildDouble(m->data, m->verts, 3 * sizeof(double), nv, m->tris, 3 * nt, 3 * sizeof(int));
    dGeomTriMeshDataPreprocess2(m->data, (1U << dTRIDATAPREPROCESS_BUILD_FACE_ANGLES), NULL);
    m->geom = dCreateTriMesh(is_dynamic ? c->mesh_dyn : c->mesh_static, m->data, NULL, NULL, NULL);
    return m->geom;
}

void mr_mesh_destroy(MrCtx *c, dGeomID g)
{
    int i;
    for (i = 0; i < c->nmesh; ++i) {
        if (c->meshes[i].geom == g) {
            MrMesh *m = &c->meshes[i];
            mr_remove_geom(c, g);
            dGeomDestroy(m->geom);
            dGeomTriMeshDataDestroy(m->data);
            free(m->verts);
            free(m->tris);
            c->meshes[i] = c->meshes[--c->nmesh];
            return;
        }
    }
}

void mr_mesh_destroy_all(MrCtx *c)
{
    while (c->nmesh > 0) mr_mesh_destroy(c, c->meshes[c->nmesh - 1].geom);
}

/* small geom helpers for meshes (no PyODE object exists for them) */
void mr_geom_set_body(dGeomID g, dBodyID b) { dGeomSetBody(g, b); }
void mr_geom_set_offset(dGeomID g, double x, double y, double z, double qw, double qx, double qy, double qz)
{
    dQuaternion q;
    q[0] = qw; q[1] = qx; q[2] = qy; q[3] = qz;
    dGeomSetOffsetPosition(g, x, y, z);
    dGeomSetOffsetQuaternion(g, q);
}
void mr_geom_set_pose(dGeomID g, double x, double y, double z, double qw, double qx, double qy, double qz)
{
    dQuaternion q;
    q[0] = qw; q[1] = qx; q[2] = qy; q[3] = qz;
    dGeomSetPosition(g, x, y, z);
    dGeomSetQuaternion(g, q);
}
void mr_geom_enable(dGeomID g, int on) { if (on) dGeomEnable(g); else dGeomDisable(g); }
int mr_geom_is_enabled(dGeomID g) { return dGeomIsEnabled(g); }
void mr_geom_set_bits(dGeomID g, unsigned long cat, unsigned long col)
{
    dGeomSetCategoryBits(g, cat);
    dGeomSetCollideBits(g, col);
}
void mr_geom_aabb(dGeomID g, double *out6)
{
    dReal a[6];
    int i;
    dGeomGetAABB(g, a);
    for (i = 0; i < 6; ++i) out6[i] = a[i];
}
/* depth of the deepest contact between two geoms (spawn overlap check), 0 if none */
double mr_max_depth(dGeomID a, dGeomID b)
{
    dContactGeom gen[MR_MAX_GEN];
    int n = dCollide(a, b, MR_MAX_GEN, gen, sizeof(dContactGeom)), i;
    double d = 0;
    for (i = 0; i < n; ++i) if (gen[i].depth > d) d = gen[i].depth;
    return d;
}

/* ---- link poses and twists -----------------------------------------------------------------
 * The pose and twist of links in the world, as Link.pose (pose_mul(body pose, T)) and Link.twist
 * (v + w x R(q) T.p, w) of physics/model.py compute them, with the same operations in the same
 * order as transforms.py, so the doubles are bit for bit those of the Python properties: 7 doubles
 * (x y z qx qy qz qw) per link into `poses`, 6 (v, w) into `twists`. A static link (body NULL) has
 * its world pose in `T` (the caller keeps it current) and a zero twist. (gazebo_ros's ModelStates
 * and LinkStates keep their poses and twists in such arrays: it points them into its message.) */
typedef struct {
    dBodyID body;
    double T[7];         /* link frame in the body frame: x y z qx qy qz qw (static: world pose) */
} MrLinkEntry;

/* transforms.quat_rotate(q = (x, y, z, w), v) */
static inline void mr_quat_rotate(const double *q, const double *v, double *out)
{
    double qx = q[0], qy = q[1], qz = q[2], qw = q[3];
    double vx = v[0], vy = v[1], vz = v[2];
    double tx = 2.0 * (qy * vz - qz * vy);
    double ty = 2.0 * (qz * vx - qx * vz);
    double tz = 2.0 * (qx * vy - qy * vx);
    out[0] = vx + qw * tx + (qy * tz - qz * ty);
    out[1] = vy + qw * ty + (qz * tx - qx * tz);
    out[2] = vz + qw * tz + (qx * ty - qy * tx);
}

/* Link.pose of a link on `body` with frame T in the body (pose_mul(body pose, T)): x y z qx qy qz qw
 * into pose; the link frame's offset R(q) T.p into r (for its twist) */
static void mr_body_link_pose(dBodyID body, const double *T, double *pose, double *r)
{
    const dReal *p = dBodyGetPosition(body);
    const dReal *qo = dBodyGetQuaternion(body);      /* ODE: w x y z */
    double qa[4] = {qo[1], qo[2], qo[3], qo[0]};
    const double *qb = T + 3;
    double ax = qa[0], ay = qa[1], az = qa[2], aw = qa[3];
    double bx = qb[0], by = qb[1], bz = qb[2], bw = qb[3];
    mr_quat_rotate(qa, T, r);
    pose[0] = p[0] + r[0]; pose[1] = p[1] + r[1]; pose[2] = p[2] + r[2];
    /* transforms.quat_mul(qa, qb) */
    pose[3] = aw * bx + ax * bw + ay * bz - az * by;
    pose[4] = aw * by - ax * bz + ay * bw + az * bx;
    pose[5] = aw * bz + ax * by - ay * bx + az * bw;
    pose[6] = aw * bw - ax * bx - ay * by - az * bz;
}

/* `poses` and `twists` need not be aligned (a message's bytes): the doubles are copied in */
void mr_link_poses(const MrLinkEntry *e, int n, void *poses, void *twists)
{
    int k;
    for (k = 0; k < n; ++k, ++e) {
        double pose[7], twist[6];
        if (!e->body) {
            memcpy(pose, e->T, 7 * sizeof(double));
            memset(twist, 0, 6 * sizeof(double));
        } else {
            const dReal *v = dBodyGetLinearVel(e->body);
            const dReal *w = dBodyGetAngularVel(e->body);
            double r[3];
            mr_body_link_pose(e->body, e->T, pose, r);
            /* Link.twist: r = quat_rotate(q, T.p); (v + cross(w, r), w) */
            twist[0] = v[0] + (w[1] * r[2] - w[2] * r[1]);
            twist[1] = v[1] + (w[2] * r[0] - w[0] * r[2]);
            twist[2] = v[2] + (w[0] * r[1] - w[1] * r[0]);
            twist[3] = w[0]; twist[4] = w[1]; twist[5] = w[2];
        }
        memcpy((char *)poses + 7 * sizeof(double) * (size_t)k, pose, sizeof(pose));
        memcpy((char *)twists + 6 * sizeof(double) * (size_t)k, twist, sizeof(twist));
    }
}

/* ---- actuators and turn counts ------------------------------------------------------------
 * The World's actuators (physics/actuators.py: one per driven joint, owned by the native backend in
 * this C memory): at every step, from the joint's state at the step's start, an output (EFFORT: the
 * command; POSITION_PID: PID on the position error; VELOCITY_PID: PID on the velocity error;
 * SEGMENT_PID: PID along a trajectory segment plus velocity feed-forward; FOLLOW_PID: PID on the
 * error to multiplier * a joint's position + offset, none inside a deadband, plus a bias effort) or
 * an ODE joint motor (MOTOR); every actuator reads its joint's state (a FOLLOW_PID also its
 * master's position) before any of them acts, so that their order changes nothing; the output is
 * an effort (OUT_EFFORT: the hardware clamp) or the ODE motor's velocity
 * (OUT_VELOCITY), then the efforts given with set_effort in that step, the joint's own clamp
 * (Joint.limit_effort) and FORCE_CAP. The pure-Python backend does the same in
 * actuators.step_python; test_actuators.py runs both on the same worlds. */
typedef struct {
    dJointID joint;      /* a hinge whose position counts whole turns (Joint.track_turns) */
    double last_raw;
    long long turns;
} MrTurn;

/* a piece of a trajectory queued behind a SEGMENT_PID actuator's own (Actuator.queue_pieces): its
 * fields as the actuator's of the same names */
#define MR_QUEUE 32      /* actuators.MAX_QUEUE */
typedef struct {
    int traj_kind, ncoef, has_offset;
    double coef[6];
    double seg_t0, seg_t1, rel_base, offset, abs_until, rel_until;
} MrPiece;

typedef struct {
    dJointID joint;
    MrTurn *turn;        /* the joint's turn count (its position = raw angle + 2 pi turns), or NULL */
    int slider;          /* 0 hinge, 1 slider */
    int kind;            /* 0 EFFORT, 1 POSITION_PID, 2 SEGMENT_PID, 3 VELOCITY_PID, 4 MOTOR, 5 FOLLOW_PID */
    int err_kind;        /* 0 target - q, 1 target clamped to [lower, upper] first, 2 shortest angle */
    int has_hw_limit;
    int antiwindup;
    int has_extra;       /* `extra` holds efforts given with set_effort for this step (Python steps) */
    double lower, upper, hw_limit, joint_limit, force_cap;
    double command, extra;
    double p, i, d, i_max, i_min;
    double p_error_last, p_error, i_error, d_error, cmd, p_term, i_term, d_term;
    double t, position, velocity, set_point, desired_velocity, out, applied;
    /* SEGMENT_PID: the desired state from one piece of a trajectory (trajectory.py, Piece): a
     * polynomial in t (traj_kind 0) or in t - rel_base (1) on [seg_t0, seg_t1], plus `offset`, or a
     * constant coef[0] (2); valid for steps starting at t < abs_until with t - rel_base < rel_until */
    int traj_kind, ncoef, has_offset;
    double coef[6];
    double seg_t0, seg_t1, rel_base, offset, ff, abs_until, rel_until;
    double max_force, accel, motor_vel;   /* MOTOR; max_force also OUT_VELOCITY's */
    int out_kind;        /* what the output drives: 0 the effort (OUT_EFFORT), 1 the ODE motor's
                          * velocity, clamped to +-vel_limit, with at most max_force (OUT_VELOCITY),
                          * 2 the joint's position, set kinematically (OUT_POSITION) */
    double vel_limit;    /* OUT_VELOCITY's clamp; OUT_POSITION's rate limit */
    int nbodies;         /* OUT_POSITION: the bodies below the joint, turned with it */
    dBodyID *bodies;
    double pos_prev;     /* OUT_POSITION: the last set-point */
    /* a watch (Actuator.watch: a gripper goal's checks): a native stretch ends before a step whose
     * start state has |watch_target - q| < watch_tol, or |dq| <= watch_vel and the joint has not
     * moved faster since watch_timeout; moved_at is the last step start with |dq| > watch_vel */
    int watch;
    double watch_target, watch_tol, watch_vel, watch_timeout, moved_at;
    /* FOLLOW_PID (Actuator.follow): the set-point is mult * the master's position (as
     * Joint.position: its turn count too; master_position, read at the step's start) +
     * follow_offset; an error below deadband gives no PID effort and leaves the PID as it is;
     * the PID's derivative is the error's change, or follow_vel - dq (has_follow_vel); bias is
     * added to the output; no master (NULL): no effort */
    dJointID master;
    MrTurn *master_turn;
    int master_slider;
    double mult, follow_offset, deadband;
    int has_follow_vel;
    double follow_vel, bias, master_position;
    /* a band (Actuator.watch_band: a trajectory goal's path tolerances), SEGMENT_PID: a native
     * stretch ends before a step whose start state has a tracking error (mr_tracking_error) with
     * |error| > band_pos (when band_pos > 0) or |error_dot| > band_vel (when band_vel > 0) */
    int band;
    double band_pos, band_vel;
    /* SEGMENT_PID: the pieces that follow its own, queue[qnext] .. queue[nqueue - 1]; the first takes
     * over at the first step whose start the actuator's piece no longer holds for (mr_piece_at) */
    int nqueue, qnext;
    MrPiece queue[MR_QUEUE];
} MrActuator;

/* sizeof(MrActuator): the ctypes mirror (backends.MrActuator) is checked against it */
size_t mr_actuator_size(void) { return sizeof(MrActuator); }

#define MR_TWO_PI 6.283185307179586

/* angles.normalize_angle(to - from) (Python: fmod twice, then > pi -> -2 pi) */
static double mr_shortest_angle(double from, double to)
{
    double a = fmod(fmod(to - from, MR_TWO_PI) + MR_TWO_PI, MR_TWO_PI);
    return a > 3.141592653589793 ? a - MR_TWO_PI : a;
}

/* Python's max(x, lo) then min(., hi) */
static inline double mr_clamp(double x, double lo, double hi)
{
    double v = lo > x ? lo : x;
    return hi < v ? hi : v;
}

/* Pid.compute(error, dt, error_dot) past its checks */
static double mr_pid_terms(MrActuator *j, double error, double error_dot, double dt)
{
    double i_term;
    j->p_error = error;
    j->d_error = error_dot;
    j->p_term = j->p * error;
    j->i_error += dt * error;
    if (j->antiwindup && j->i != 0.0) {
        double a = j->i_min / j->i, b = j->i_max / j->i;
        double lo = b < a ? b : a, hi = b < a ? a : b;
        j->i_error = mr_clamp(j->i_error, lo, hi);
    }
    i_term = j->i * j->i_error;
    if (!j->antiwindup) i_term = mr_clamp(i_term, j->i_min, j->i_max);
    j->i_term = i_term;
    j->d_term = j->d * error_dot;
    j->cmd = j->p_term + i_term + j->d_term;
    return j->cmd;
}

/* Pid.compute(error, dt) */
static double mr_pid(MrActuator *j, double error, double dt)
{
    double error_dot;
    if (dt <= 0.0 || !isfinite(error)) return 0.0;
    error_dot = (error - j->p_error_last) / dt;
    j->p_error_last = error;
    if (!isfinite(error_dot)) return 0.0;
    return mr_pid_terms(j, error, error_dot, dt);
}

/* Pid.compute(error, dt, error_dot) */
static double mr_pid_dot(MrActuator *j, double error, double error_dot, double dt)
{
    if (dt <= 0.0 || !isfinite(error)) return 0.0;
    if (!isfinite(error_dot)) return 0.0;
    return mr_pid_terms(j, error, error_dot, dt);
}

/* actuators.piece_at: the queued pieces take over, in order, while the actuator's piece does not
 * hold for a step starting at t (t >= abs_until or t - rel_base >= rel_until: Piece's tests) */
static void mr_piece_at(MrActuator *j, double t)
{
    while (j->qnext < j->nqueue && (t >= j->abs_until || t - j->rel_base >= j->rel_until)) {
        const MrPiece *p = &j->queue[j->qnext++];
        j->traj_kind = p->traj_kind;
        j->ncoef = p->ncoef;
        j->has_offset = p->has_offset;
        memcpy(j->coef, p->coef, sizeof j->coef);
        j->seg_t0 = p->seg_t0;
        j->seg_t1 = p->seg_t1;
        j->rel_base = p->rel_base;
        j->offset = p->offset;
        j->abs_until = p->abs_until;
        j->rel_until = p->rel_until;
    }
}

/* actuators.segment_sample: eval_polynomial's sums of ck * s ** k in the same order at
 * s = segment_time(t) (Python's float ** int is C's pow) */
static void mr_segment_sample(const MrActuator *j, double t, double *pos, double *vel)
{
    double tt, s, lo, p = 0.0, v = 0.0;
    int k;
    if (j->traj_kind == 2) {
        *pos = j->coef[0];
        *vel = 0.0;
        return;
    }
    tt = j->traj_kind == 1 ? t - j->rel_base : t;
    lo = j->seg_t0 > tt ? j->seg_t0 : tt;                     /* min(max(t, t0), t1) - t0 */
    s = (j->seg_t1 < lo ? j->seg_t1 : lo) - j->seg_t0;
    for (k = 0; k < j->ncoef; ++k) {
        p += j->coef[k] * pow(s, (double)k);
        if (k >= 1) v += (double)k * j->coef[k] * pow(s, (double)(k - 1));
    }
    *pos = j->has_offset ? p + j->offset : p;
    *vel = v;
}

/* actuators.tracking_error of a SEGMENT_PID actuator at t for the joint at (q, v): the segment's
 * desired (position, velocity) and the errors desired - q (err_kind 2: the shortest angle from q)
 * and desired velocity - v */
static void mr_tracking_error(const MrActuator *j, double t, double q, double v, double *dpos, double *dvel,
                              double *error, double *error_dot)
{
    mr_segment_sample(j, t, dpos, dvel);
    *error = j->err_kind == 2 ? mr_shortest_angle(q, *dpos) : *dpos - q;
    *error_dot = *dvel - v;
}

/* actuators.saturate_position */
static double mr_saturate_position(int rule, double prev, double target, double vel_limit, double dt,
                                   double lower, double upper)
{
    if (rule == 2) target = prev + mr_shortest_angle(prev, target);
    if (vel_limit < INFINITY && dt > 0.0) {
        double step = vel_limit * dt;
        target = mr_clamp(target, prev - step, prev + step);
    }
    if (rule != 2) target = mr_clamp(target, lower, upper);
    return target;
}

/* actuators.place_subtree: the bodies below the joint turned (slid) rigidly about its axis by
 * delta, then moving with the joint's parent body (at rest without one) */
static void mr_place_subtree(const MrActuator *j, double delta)
{
    dJointID oj = j->joint;
    dBodyID parent = dJointGetBody(oj, 1);
    dVector3 ax, a;
    double qx = 0, qy = 0, qz = 0, qw = 1;
    int k;
    if (j->slider) dJointGetSliderAxis(oj, ax);
    else {
        double h = 0.5 * delta, sh = sin(h);
        dJointGetHingeAxis(oj, ax);
        dJointGetHingeAnchor(oj, a);
        qx = ax[0] * sh; qy = ax[1] * sh; qz = ax[2] * sh; qw = cos(h);
    }
    for (k = 0; k < j->nbodies; ++k) {
        dBodyID b = j->bodies[k];
        const dReal *p = dBodyGetPosition(b);
        double n[3];
        if (!j->slider) {
            double rx = p[0] - a[0], ry = p[1] - a[1], rz = p[2] - a[2];
            double tx = 2.0 * (qy * rz - qz * ry);
            double ty = 2.0 * (qz * rx - qx * rz);
            double tz = 2.0 * (qx * ry - qy * rx);
            const dReal *o = dBodyGetQuaternion(b);           /* w x y z */
            dQuaternion nq;
            n[0] = a[0] + (rx + qw * tx + (qy * tz - qz * ty));
            n[1] = a[1] + (ry + qw * ty + (qz * tx - qx * tz));
            n[2] = a[2] + (rz + qw * tz + (qx * ty - qy * tx));
            nq[0] = qw * o[0] - qx * o[1] - qy * o[2] - qz * o[3];
            nq[1] = qw * o[1] + qx * o[0] + qy * o[3] - qz * o[2];
            nq[2] = qw * o[2] + qy * o[0] + qz * o[1] - qx * o[3];
            nq[3] = qw * o[3] + qz * o[0] + qx * o[2] - qy * o[1];
            dBodySetPosition(b, n[0], n[1], n[2]);
            dBodySetQuaternion(b, nq);
        } else {
            n[0] = p[0] + ax[0] * delta;
            n[1] = p[1] + ax[1] * delta;
            n[2] = p[2] + ax[2] * delta;
            dBodySetPosition(b, n[0], n[1], n[2]);
        }
        if (!parent) {
            dBodySetLinearVel(b, 0, 0, 0);
            dBodySetAngularVel(b, 0, 0, 0);
        } else {
            const dReal *pv = dBodyGetLinearVel(parent), *pw = dBodyGetAngularVel(parent);
            const dReal *pp = dBodyGetPosition(parent);
            double rx = n[0] - pp[0], ry = n[1] - pp[1], rz = n[2] - pp[2];
            dBodySetLinearVel(b, pv[0] + (pw[1] * rz - pw[2] * ry), pv[1] + (pw[2] * rx - pw[0] * rz),
                              pv[2] + (pw[0] * ry - pw[1] * rx));
            dBodySetAngularVel(b, pw[0], pw[1], pw[2]);
        }
    }
}

static inline double mr_joint_position(dJointID joint, int slider, const MrTurn *turn)
{
    if (slider) return dJointGetSliderPosition(joint);
    return dJointGetHingeAngle(joint) + (turn ? MR_TWO_PI * (double)turn->turns : 0.0);
}

static inline double mr_joint_velocity(dJointID joint, int slider)
{
    return slider ? dJointGetSliderPositionRate(joint) : dJointGetHingeAngleRate(joint);
}

/* Actuator.tracking_error: out[0] the position error, out[1] the velocity error of a SEGMENT_PID
 * actuator at t from its joint's state now (what its step at t would compute) */
void mr_actuator_tracking_error(MrActuator *j, double t, double *out)
{
    double dpos, dvel;
    mr_piece_at(j, t);
    mr_tracking_error(j, t, mr_joint_position(j->joint, j->slider, j->turn), mr_joint_velocity(j->joint, j->slider),
                      &dpos, &dvel, &out[0], &out[1]);
}

static void mr_set_param(dJointID j, int slider, int param, double v)
{
    if (slider) dJointSetSliderParam(j, param, v);
    else dJointSetHingeParam(j, param, v);
}

/* actuators._apply_effort: f plus the efforts given with set_effort for this step, through the
 * joint's clamp (Joint.limit_effort: its effort limit, FORCE_CAP), to the joint */
static void mr_apply_effort(MrActuator *j, double f)
{
    double lim = j->joint_limit;
    if (j->has_extra) {
        f += j->extra;
        j->has_extra = 0;
        j->extra = 0.0;
    }
    if (lim > 0.0) {
        if (f > lim) f = lim;
        else if (f < -lim) f = -lim;
    }
    if (f > j->force_cap) f = j->force_cap;
    else if (f < -j->force_cap) f = -j->force_cap;
    if (j->slider) dJointAddSliderForce(j->joint, f);
    else dJointAddHingeTorque(j->joint, f);
    j->applied = f;
}

/* every actuator's step at time t (actuators.apply_python: first every actuator's read_python,
 * then every step_python): dParamVel / dParamFMax are the running libode's parameter numbers
 * (odelib.PARAM_VEL, PARAM_FMAX) */
void mr_apply_actuators(MrActuator **acts, int n, double t, double dt, int param_vel, int param_fmax)
{
    int k;
    for (k = 0; k < n; ++k) {
        MrActuator *j = acts[k];
        j->t = t;
        if (j->kind == 2) mr_piece_at(j, t);
        j->position = mr_joint_position(j->joint, j->slider, j->turn);
        j->velocity = mr_joint_velocity(j->joint, j->slider);
        if (j->kind == 5 && j->master)
            j->master_position = mr_joint_position(j->master, j->master_slider, j->master_turn);
    }
    for (k = 0; k < n; ++k) {
        MrActuator *j = acts[k];
        double f, q = j->position, v = j->velocity;
        if (j->out_kind == 2) {
            double target, dvel = 0.0;
            if (j->kind == 2) mr_segment_sample(j, t, &target, &dvel);
            else target = j->command;
            j->desired_velocity = dvel;
            j->set_point = target;
            if (!isfinite(target)) target = j->pos_prev;
            target = mr_saturate_position(j->err_kind, j->pos_prev, target, j->vel_limit, dt, j->lower, j->upper);
            j->pos_prev = j->out = target;
            mr_place_subtree(j, target - q);
            if (j->turn) {                                        /* Joint.turned_to */
                double raw = dJointGetHingeAngle(j->joint);
                j->turn->turns = (long long)nearbyint((target - raw) / MR_TWO_PI);
                j->turn->last_raw = raw;
            }
            mr_apply_effort(j, 0.0);
            continue;
        }
        if (j->kind == 1) {
            double target = j->command, error;
            j->set_point = target;
            j->desired_velocity = 0.0;
            if (j->err_kind == 2) error = mr_shortest_angle(q, target);
            else if (j->err_kind == 1) error = mr_clamp(target, j->lower, j->upper) - q;
            else error = target - q;
            f = mr_pid(j, error, dt);
        } else if (j->kind == 2) {
            double dpos, dvel, error, error_dot;
            mr_tracking_error(j, t, q, v, &dpos, &dvel, &error, &error_dot);
            j->set_point = dpos;
            j->desired_velocity = dvel;
            f = mr_pid_dot(j, error, error_dot, dt) + j->ff * dvel;
        } else if (j->kind == 3) {
            j->set_point = j->command;
            j->desired_velocity = j->command;
            f = mr_pid(j, j->command - v, dt);
        } else if (j->kind == 4) {
            double target = j->command;
            if (j->accel > 0.0) {
                double step = j->accel * dt;
                target = mr_clamp(target, j->motor_vel - step, j->motor_vel + step);
            }
            j->motor_vel = target;
            j->set_point = j->desired_velocity = target;
            j->out = 0.0;
            mr_set_param(j->joint, j->slider, param_vel, target);
            mr_set_param(j->joint, j->slider, param_fmax, j->max_force);
            continue;
        } else if (j->kind == 5) {
            j->desired_velocity = j->has_follow_vel ? j->follow_vel : 0.0;
            if (!j->master) {
                j->set_point = q;
                f = 0.0;
            } else {
                double target = j->mult * j->master_position + j->follow_offset;
                double error = target - q;
                j->set_point = target;
                if (fabs(error) < j->deadband) f = 0.0;
                else if (j->has_follow_vel) f = mr_pid_dot(j, error, j->follow_vel - v, dt);
                else f = mr_pid(j, error, dt);
                f += j->bias;
            }
        } else {
            f = j->set_point = j->command;
            j->desired_velocity = 0.0;
        }
        j->out = f;
        if (!isfinite(f)) f = 0.0;
        if (j->out_kind == 1) {
            mr_set_param(j->joint, j->slider, param_vel, mr_clamp(f, -j->vel_limit, j->vel_limit));
            mr_set_param(j->joint, j->slider, param_fmax, j->max_force);
            f = 0.0;
        } else if (j->has_hw_limit) f = mr_clamp(f, -j->hw_limit, j->hw_limit);
        mr_apply_effort(j, f);
    }
}

/* Joint.track_turns of every turn-counting joint, after a step */
void mr_track_turns(MrTurn **turns, int n)
{
    int k;
    for (k = 0; k < n; ++k) {
        MrTurn *u = turns[k];
        double raw = dJointGetHingeAngle(u->joint);
        double d = raw - u->last_raw;
        if (d > 3.141592653589793) u->turns -= 1;
        else if (d < -3.141592653589793) u->turns += 1;
        u->last_raw = raw;
    }
}

/* ---- model actuators ----------------------------------------------------------------------
 * The World's model-level actuators (physics/actuators.py, World.add_model_actuator), before the
 * joint actuators of every step. PLANAR_VELOCITY (0): the model moves at (vx, vy) in its base
 * link's heading and turns at wz about the vertical, its vertical velocity 0: every body of the
 * model gets the rigid twist of the base link's frame (Model.set_twist), the heading (the yaw of
 * transforms.rpy_from_quat) read from the base's pose at the step's start. The pure-Python
 * backend does the same in actuators.step_model_python. */
typedef struct {
    int kind;            /* 0 PLANAR_VELOCITY */
    int nbodies;
    dBodyID base;        /* the body of the model's canonical link */
    dBodyID *bodies;     /* every body of the model (Model.bodies) */
    double T[7];         /* the canonical link's frame in its body: x y z qx qy qz qw */
    double vx, vy, wz;   /* the command: m/s in the heading, rad/s */
} MrModelActuator;

void mr_apply_model_actuators(MrModelActuator **acts, int n)
{
    int k, i;
    for (k = 0; k < n; ++k) {
        const MrModelActuator *a = acts[k];
        double pose[7], r[3], yaw, c, s, lin[3], ang[3];
        double x, y, z, w;
        mr_body_link_pose(a->base, a->T, pose, r);
        x = pose[3]; y = pose[4]; z = pose[5]; w = pose[6];
        yaw = atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z));
        c = cos(yaw);
        s = sin(yaw);
        lin[0] = a->vx * c - a->vy * s;
        lin[1] = a->vy * c + a->vx * s;
        lin[2] = 0.0;
        ang[0] = 0.0; ang[1] = 0.0; ang[2] = a->wz;
        for (i = 0; i < a->nbodies; ++i) {
            dBodyID b = a->bodies[i];
            const dReal *p = dBodyGetPosition(b);
            double d[3] = {p[0] - pose[0], p[1] - pose[1], p[2] - pose[2]};
            /* transforms.cross(ang, d) */
            double cx = ang[1] * d[2] - ang[2] * d[1];
            double cy = ang[2] * d[0] - ang[0] * d[2];
            double cz = ang[0] * d[1] - ang[1] * d[0];
            dBodySetLinearVel(b, lin[0] + cx, lin[1] + cy, lin[2] + cz);
            dBodySetAngularVel(b, ang[0], ang[1], ang[2]);
            dBodyEnable(b);
        }
    }
}

/* ---- native stretches of steps ------------------------------------------------------------
 * Several whole steps in one call, up to the first step at which a Python hook of the World is due
 * (World.step decides that from the hooks' due times: docs/design/sim_core_api.md). Each step does
 * what World._step_once does for a world without wrenches, anti-gravity groups, frozen models or
 * queued efforts: the model actuators (mr_apply_model_actuators), the joint actuators
 * (mr_apply_actuators), explicit damping, the mimic joints' couplings
 * and the soft limits' stops (MrStretchMimic, MrStretchSoft), collide + quickStep or dWorldStep
 * with the guard's velocity scan (mr_step_checked), time and iteration count, the turn counts, then
 * the observer (a C function the World was given, e.g. gazebo_ros's /clock: physics knows nothing
 * of it). A step the guard must look at (a flagged step, a snapshot step) ends the stretch
 * (`guard` = 1: the World's Python guard runs for it); so does a step whose after-hooks are due
 * (`after` = 1), the end of a segment actuator's piece (before its step), an actuator's watch or
 * band that fires (before its step: mr_stretch_watches) and a wake-up (`*wake`, set by World.wake from any
 * thread). */

/* a mimic joint (Joint.drive_mimic) and its master; positions as Joint.position */
typedef struct {
    dJointID joint, master;
    MrTurn *turn, *master_turn;
    int slider, master_slider, has_lower, has_upper;
    double mult, offset, lower, upper, child_inertia;
} MrStretchMimic;

/* a revolute joint with limits beyond +-pi (Joint.update_soft_limits) */
typedef struct {
    dJointID joint;
    MrTurn *turn;
    double lower, upper;
} MrStretchSoft;

/* called after every step of a stretch with the new simulated time */
typedef void (*mr_observer_fn)(void *user, double t);

typedef struct {
    MrActuator **acts;
    int nacts;
    int ndamp;
    dJointID *damp_joints;
    int *damp_kinds;
    double *damp_coef;
    dBodyID *bodies;
    int nbodies;
    int nturns;
    MrTurn **turns;
    int guard_max_contacts;
    int max_contacts;
    int snapshot_interval;
    double vmax2, wmax2;
    double dt, gx, gy, gz, layer;
    double time;         /* in: before the first step; out: after the last */
    double last_start;   /* out: the time at which the last step started */
    long long iterations;
    double before_due;   /* no step starts at t >= before_due (a before-hook is due) */
    double after_due;    /* a step that ends at t with t + 1e-12 >= after_due ends the stretch:
                          * its after-hooks are due (`after`) */
    volatile int *wake;  /* non-zero: end the stretch after the step in progress (World.wake) */
    void *observer;      /* mr_observer_fn, or NULL */
    void *observer_user;
    int ncontacts;       /* out: contacts of the last step */
    int guard;           /* out: 1 when the World's guard must look at the last step */
    int world_step;      /* as mr_step_checked: 0 quickStep, 1 dWorldStep */
    int first_bad;       /* out: mr_step_checked's guard scan of the last step */
    int after;           /* out: 1 when the last step's after-hooks are due (Python runs them) */
    int nmimic;
    MrStretchMimic *mimics;
    int nsoft;
    MrStretchSoft *softs;
    int param_vel, param_fmax, param_lo_stop, param_hi_stop;   /* odelib.PARAM_* of this libode */
    double mimic_gain, mimic_force;                           /* MIMIC_GAIN, MIMIC_COUPLING_FORCE */
    MrModelActuator **macts;                                  /* the model actuators, before the joints' */
    int nmacts;
    /* the guard's snapshot of a step on its interval at which nothing was flagged, taken here
     * instead of ending the stretch (NULL: end it, the World's guard takes it in Python): per body
     * of `bodies` MR_SNAP_BODY doubles (position, quaternion w x y z, linear and angular
     * velocity), per turn record of `turns` 2 (last_raw, turns) */
    double *snap;
    double *snap_turns;
    long long snap_iter;  /* out: the iteration count after the step of the last snapshot taken */
    /* the efforts queued for the first step (set_effort on joints without an actuator, already
     * clamped: Joint.queued_effort), applied after the model actuators as World._apply_forces
     * does (Joint.apply_command); kinds: 0 hinge, 1 slider */
    int nefforts;
    dJointID *effort_joints;
    int *effort_kinds;
    double *effort_values;
} MrStretch;

#define MR_SNAP_BODY 13

static void mr_stretch_snapshot(MrStretch *b)
{
    int i;
    for (i = 0; i < b->nbodies; ++i) {
        dBodyID body = b->bodies[i];
        double *o = b->snap + (size_t)i * MR_SNAP_BODY;
        const dReal *p = dBodyGetPosition(body), *q = dBodyGetQuaternion(body);
        const dReal *v = dBodyGetLinearVel(body), *w = dBodyGetAngularVel(body);
        o[0] = p[0]; o[1] = p[1]; o[2] = p[2];
        o[3] = q[0]; o[4] = q[1]; o[5] = q[2]; o[6] = q[3];
        o[7] = v[0]; o[8] = v[1]; o[9] = v[2];
        o[10] = w[0]; o[11] = w[1]; o[12] = w[2];
    }
    for (i = 0; i < b->nturns; ++i) {
        b->snap_turns[2 * i] = b->turns[i]->last_raw;
        b->snap_turns[2 * i + 1] = (double)b->turns[i]->turns;
    }
    b->snap_iter = b->iterations;
}

/* World._apply_forces after the damping: Joint.drive_mimic of every mimic joint, then
 * Joint.update_soft_limits of every joint with limits beyond +-pi */
static void mr_stretch_mimics_and_soft_limits(MrStretch *b)
{
    int k;
    for (k = 0; k < b->nmimic; ++k) {
        const MrStretchMimic *m = &b->mimics[k];
        double q = mr_joint_position(m->joint, m->slider, m->turn);
        double qm = mr_joint_position(m->master, m->master_slider, m->master_turn);
        double v = b->mimic_gain * (qm * m->mult + m->offset - q) / b->dt;
        double fmax = b->mimic_force;
        if ((m->has_lower && q <= m->lower) || (m->has_upper && q >= m->upper)) {
            double vel = m->slider ? dJointGetSliderPositionRate(m->joint) : dJointGetHingeAngleRate(m->joint);
            double f = m->child_inertia * fabs(v - vel) / b->dt;
            if (f < fmax) fmax = f;                               /* min(fmax, f) */
        }
        mr_set_param(m->joint, m->slider, b->param_vel, v);
        mr_set_param(m->joint, m->slider, b->param_fmax, fmax);
    }
    for (k = 0; k < b->nsoft; ++k) {
        const MrStretchSoft *u = &b->softs[k];
        double turns = MR_TWO_PI * (double)(u->turn ? u->turn->turns : 0);
        double lo = u->lower - turns, hi = u->upper - turns;
        dJointSetHingeParam(u->joint, b->param_lo_stop, lo > -3.141592653589793 ? lo : -dInfinity);
        dJointSetHingeParam(u->joint, b->param_hi_stop, hi < 3.141592653589793 ? hi : dInfinity);
    }
}

/* the efforts queued for the stretch's first step */
static void mr_stretch_efforts(const MrStretch *b)
{
    int k;
    for (k = 0; k < b->nefforts; ++k) {
        if (b->effort_kinds[k]) dJointAddSliderForce(b->effort_joints[k], b->effort_values[k]);
        else dJointAddHingeTorque(b->effort_joints[k], b->effort_values[k]);
    }
}

/* 1 when a segment actuator's piece, and every piece queued behind it, do not hold for a step
 * starting at t */
static int mr_stretch_pieces_end(const MrStretch *b, double t)
{
    int k;
    for (k = 0; k < b->nacts; ++k) {
        MrActuator *j = b->acts[k];
        if (j->kind != 2) continue;
        mr_piece_at(j, t);
        if (t >= j->abs_until || t - j->rel_base >= j->rel_until) return 1;
    }
    return 0;
}

/* 1 when a watched actuator's check is due for a step starting at t: a watch (Actuator.watch; the
 * checks in GripperActionController's update, in its order; notes the steps at which the joint
 * moves) or a band the tracking error leaves (Actuator.watch_band: the path tolerances of
 * JointTrajectoryController's update) */
static int mr_stretch_watches(MrStretch *b, double t)
{
    int k;
    for (k = 0; k < b->nacts; ++k) {
        MrActuator *j = b->acts[k];
        double q, v;
        int band = j->band && j->kind == 2;
        if (!j->watch && !band) continue;
        q = mr_joint_position(j->joint, j->slider, j->turn);
        v = mr_joint_velocity(j->joint, j->slider);
        if (band) {
            double dpos, dvel, e, edot;
            mr_piece_at(j, t);
            mr_tracking_error(j, t, q, v, &dpos, &dvel, &e, &edot);
            if ((j->band_pos > 0.0 && fabs(e) > j->band_pos) || (j->band_vel > 0.0 && fabs(edot) > j->band_vel))
                return 1;
        }
        if (!j->watch) continue;
        if (fabs(j->watch_target - q) < j->watch_tol) return 1;
        if (fabs(v) > j->watch_vel) j->moved_at = t;
        else if (t - j->moved_at > j->watch_timeout) return 1;
    }
    return 0;
}

/* The simulated time a step of dt after t, on the nanosecond grid (world.next_time: the nearest
 * whole nanosecond, ties to even as Python's round) */
static double mr_next_time(double t, double dt)
{
    return nearbyint((t + dt) * 1e9) / 1e9;
}

/* Up to n steps; returns the number done (0 when the first step is due for Python). */
int mr_run_steps(MrCtx *c, MrStretch *b, int n)
{
    int k;
    b->guard = 0;
    b->after = 0;
    for (k = 0; k < n; ++k) {
        double t = b->time, tn = mr_next_time(t, b->dt);
        int after = tn + 1e-12 >= b->after_due, snapshot;
        if (t >= b->before_due || mr_stretch_pieces_end(b, t) || (b->wake && *b->wake) ||
            mr_stretch_watches(b, t)) break;
        b->last_start = t;
        if (b->nmacts) mr_apply_model_actuators(b->macts, b->nmacts);
        if (k == 0 && b->nefforts) mr_stretch_efforts(b);
        mr_apply_actuators(b->acts, b->nacts, t, b->dt, b->param_vel, b->param_fmax);
        if (b->ndamp) mr_apply_damping(b->damp_joints, b->damp_kinds, b->damp_coef, b->ndamp);
        if (b->nmimic || b->nsoft) mr_stretch_mimics_and_soft_limits(b);
        b->ncontacts = mr_step_checked(c, b->dt, b->gx, b->gy, b->gz, b->layer, b->max_contacts, b->world_step,
                                       b->bodies, b->nbodies, b->vmax2, b->wmax2, &b->first_bad);
        b->iterations += 1;
        b->time = tn;
        mr_track_turns(b->turns, b->nturns);
        if (b->observer) ((mr_observer_fn)b->observer)(b->observer_user, tn);
        snapshot = b->snapshot_interval > 0 && b->iterations % b->snapshot_interval == 0;
        if (b->first_bad >= 0 || b->ncontacts > b->guard_max_contacts || (snapshot && !b->snap)) {
            b->guard = 1;
            b->after = after;
            return k + 1;
        }
        if (snapshot) mr_stretch_snapshot(b);
        if (after) {
            b->after = 1;
            return k + 1;
        }
    }
    return k;
}

/* the SHA-256 of this file as the build saw it (CMakeLists.txt): the loader compares it with the
 * source next to it and refuses a library built from another one */
#ifndef MODROB_SOURCE_SHA256
#define MODROB_SOURCE_SHA256 ""
#endif
const char *modrob_source_sha256(void) { return MODROB_SOURCE_SHA256; }
