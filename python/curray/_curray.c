/* curray._curray: the C side of the Python package (python/README section of
 * the top README). It calls the same library as the command line: the scene
 * and configuration loaders (src/input, src/output), the backend choice and
 * the frame stack over the backends (src/render: backend.h, run.h) and the
 * core trace loop (src/core, with its path recorder for trace()). Every failure
 * comes back as a cr_err message and is raised as ValueError (bad input) or
 * MemoryError; nothing here exits or prints.
 *
 * A render comes back as one bytearray per array, filled in one pass over
 * the pixels with the GIL released (the CSV's values, cr_pixel_csv_values);
 * the Python side wraps each with numpy.frombuffer, without a copy. */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <stdatomic.h>
#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "render/backend.h"
#include "render/cpu.h"
#include "render/gpu.h"
#include "render/run.h"
#include "output/info.h"
#include "output/orbit_picture.h"
#include "output/output.h"
#include "output/raypath.h"
#include "output/spectrum.h"
#include "output/worldline.h"
#include "input/scene.h"
#include "input/sysconfig.h"

/* One frame ready to trace: the loaded scene, the settings and the frame. */
typedef struct cr_py_job {
    cr_scene scene;
    int scene_loaded;
    cr_sysconfig cfg;
    cr_frame_eval eval; /* the frame (eval.frame) with its spheres */
} cr_py_job;

static void cr_py_job_free(cr_py_job *j)
{
    if (j->scene_loaded)
        cr_scene_free(&j->scene);
    cr_frame_eval_free(&j->eval);
    j->scene_loaded = 0;
}

static PyObject *cr_py_value_error(const char *prefix, const cr_err *err)
{
    PyErr_Format(PyExc_ValueError, "%s%s", prefix, err->msg);
    return NULL;
}

/* Load and prepare frame k of n of the scene (text or path) at width x
 * height with the configuration text (YAML, the keys of config.yml). The
 * messages are the command line's: "scene file <file>:<line>:<col>: ...",
 * "configuration file ...". Returns 0, or -1 with a Python exception set. */
static int cr_py_prepare(cr_py_job *j, const char *scene_text, Py_ssize_t scene_len,
                         const char *scene_name, int is_path, const char *cfg_text,
                         Py_ssize_t cfg_len, long width, long height, long k, long n)
{
    cr_trace_settings ts;
    cr_err err;
    memset(j, 0, sizeof *j);
    err.msg[0] = '\0';
    if (width < 1 || width > CR_MAX_SIDE || height < 1 || height > CR_MAX_SIDE ||
        width * height > CR_MAX_PIXELS) {
        PyErr_Format(PyExc_ValueError,
                     "width, height: expected 1 to %ld pixels a side and at most %ld pixels, "
                     "got %ld x %ld",
                     CR_MAX_SIDE, CR_MAX_PIXELS, width, height);
        return -1;
    }
    if (n < 1 || n > CR_MAX_FRAMES || k < 0 || k >= n) {
        PyErr_Format(PyExc_ValueError,
                     "frame, frames: expected 0 <= frame < frames <= %ld, got frame %ld of %ld",
                     CR_MAX_FRAMES, k, n);
        return -1;
    }
    cr_sysconfig_defaults(&j->cfg);
    if (cr_sysconfig_load_string(cfg_text, (size_t)cfg_len, "(keyword arguments)", &j->cfg,
                                 &err)) {
        cr_py_value_error("configuration ", &err);
        return -1;
    }
    if ((is_path ? cr_scene_load(scene_text, &j->scene, &err)
                 : cr_scene_load_string(scene_text, (size_t)scene_len, scene_name, &j->scene,
                                        &err))) {
        cr_py_value_error("scene file ", &err);
        return -1;
    }
    j->scene_loaded = 1;
    ts = j->cfg.raytracer;
    /* accretion.exposure: auto, as the command line finds it (from frame 0) */
    if (cr_scene_auto_exposure(&j->scene, (int)n, (int)width, (int)height, &ts, NULL, &err) ||
        cr_frame_eval_at(&j->eval, &j->scene, (int)k, (int)n, (int)width, (int)height, &ts,
                         &err)) {
        cr_py_job_free(j);
        cr_py_value_error("scene file ", &err);
        return -1;
    }
    j->eval.frame.science = 1; /* every array is read for its values */
    return 0;
}

static char *render_kw[] = {"scene", "is_path", "name", "config", "width", "height",
                            "frame", "frames", "backend", NULL};

/* The arrays of _render, by name: element size; filled by cr_py_fill. */
enum { CR_A_RGB, CR_A_REDSHIFT, CR_A_OUTCOME, CR_A_STEPS, CR_A_ERR_MEAN, CR_A_ERR_STD,
       CR_A_HIT_R, CR_A_HIT_PHI, CR_A_BOLO, CR_A_OBJECT, CR_A_ORDER, CR_A_THTURNS, CR_A_DELAY, CR_A_N };
static const struct {
    const char *name;
    size_t size;
} cr_py_arrays[CR_A_N] = {{"rgb", 3},        {"redshift", 8}, {"outcome", 1},
                          {"steps", 4},      {"err_mean", 8}, {"err_std", 8},
                          {"hit_r", 8},      {"hit_phi", 8},  {"bolometric", 8},
                          {"object", 2},     {"order", 2},    {"theta_turns", 2},
                          {"delay", 8}};

/* One pass from the pixels to the arrays, with the CSV's values
 * (cr_pixel_csv_values: -1 where the CSV writes -1). */
static void cr_py_fill(const cr_pixel *px, size_t n, char **a)
{
    size_t i;
    for (i = 0; i < n; i++) {
        const cr_pixel *q = &px[i];
        cr_pixel_values v = cr_pixel_csv_values(q);
        a[CR_A_RGB][3 * i] = (char)q->color.r;
        a[CR_A_RGB][3 * i + 1] = (char)q->color.g;
        a[CR_A_RGB][3 * i + 2] = (char)q->color.b;
        ((double *)a[CR_A_REDSHIFT])[i] = v.redshift;
        a[CR_A_OUTCOME][i] = (char)q->outcome;
        ((uint32_t *)a[CR_A_STEPS])[i] = q->steps;
        ((double *)a[CR_A_ERR_MEAN])[i] = q->err_mean;
        ((double *)a[CR_A_ERR_STD])[i] = q->err_std;
        ((double *)a[CR_A_HIT_R])[i] = v.hit_r;
        ((double *)a[CR_A_HIT_PHI])[i] = v.hit_phi;
        ((double *)a[CR_A_BOLO])[i] = v.bolometric;
        ((int16_t *)a[CR_A_OBJECT])[i] = q->object;
        ((int16_t *)a[CR_A_ORDER])[i] = (int16_t)v.order;
        ((int16_t *)a[CR_A_THTURNS])[i] = (int16_t)v.theta_turns;
        ((double *)a[CR_A_DELAY])[i] = v.delay;
    }
}

/* The render in progress, as the calling thread sees it while the GIL is
 * released: its thread state, the cancel flag the workers read, and whether
 * a Python signal handler raised (Ctrl-C: KeyboardInterrupt). */
typedef struct cr_py_wait {
    PyThreadState *ts;
    atomic_int cancel;
    int raised;
} cr_py_wait;

/* Called from the calling thread while the render runs (the backend's
 * progress: the CPU's about every 0.25 s, the GPU's after each chunk of
 * rows): take the GIL only to run Python's signal handlers, and set the
 * cancel flag when one raised. Returns 1 when the render is to stop. */
static int cr_py_poll(void *ctx)
{
    cr_py_wait *w = ctx;
    if (w->raised)
        return 1;
    PyEval_RestoreThread(w->ts);
    if (PyErr_CheckSignals() != 0) {
        w->raised = 1;
        atomic_store(&w->cancel, 1);
    }
    w->ts = PyEval_SaveThread();
    return w->raised;
}

static void cr_py_progress(void *ctx, int rows_done, int rows_total)
{
    (void)rows_done;
    (void)rows_total;
    (void)cr_py_poll(ctx);
}

/* The command line's backend choice (--backend, cr_backend_choose): "cuda"
 * when asked for, or ("auto") when a GPU enabled in the configuration is
 * usable, else the CPU. Returns the device to trace on, -1 for the CPU, or
 * -2 with ValueError set ("cuda" without a usable GPU: the reason; a name
 * that is not a backend). */
static int cr_py_backend(const char *backend, const cr_sysconfig *cfg)
{
    int devices[CR_MAX_GPUS];
    cr_backend_choice want;
    cr_err gerr;
    if (strcmp(backend, "cpu") == 0)
        want = CR_BACKEND_CPU;
    else if (strcmp(backend, "cuda") == 0)
        want = CR_BACKEND_CUDA;
    else if (strcmp(backend, "auto") == 0)
        want = CR_BACKEND_AUTO;
    else {
        PyErr_Format(PyExc_ValueError, "backend: expected auto, cpu or cuda, got '%s'",
                     backend);
        return -2;
    }
    switch (cr_backend_choose(want, cfg->gpu_enabled, CR_MAX_GPUS, devices, CR_MAX_GPUS,
                              &gerr)) {
    case 0:
        return -1;
    case -1:
        PyErr_Format(PyExc_ValueError, "backend cuda: %s", gerr.msg);
        return -2;
    default:
        return devices[0];
    }
}

/* The frame stack (render/run.h) of one frame, the job's: prepare hands
 * out the frame prepared already, deliver fills the arrays a (render) or
 * sums the spectrum spec of the traced pixels (spectrum; a is NULL). */
typedef struct cr_py_run {
    const cr_py_job *j;
    char **a;
    cr_spectrum *spec;
    cr_py_wait *w;
} cr_py_run;

static int cr_py_stack_prepare(void *ctx, int k, void **slot, const cr_frame **f, cr_err *err)
{
    (void)k;
    (void)slot; /* the frame stays the job's (nothing to release) */
    (void)err;
    *f = &((cr_py_run *)ctx)->j->eval.frame;
    return 0;
}

static int cr_py_stack_deliver(void *ctx, int worker, const cr_traced *t, cr_err *err)
{
    cr_py_run *r = ctx;
    (void)worker;
    if (r->w->raised)
        return 0;
    if (r->spec)
        return cr_spectrum_compute(t->frame, t->px, &r->j->scene.spectrum, r->spec, err);
    cr_py_fill(t->px, (size_t)t->frame->width * (size_t)t->frame->height, r->a);
    return 0;
}

static void cr_py_stack_progress(void *ctx, int worker, const cr_item *it, int rows_done,
                                 int rows_total)
{
    (void)worker;
    (void)it;
    cr_py_progress(((cr_py_run *)ctx)->w, rows_done, rows_total);
}

/* Trace the frame on the opened backend b through the frame stack, as the
 * command line does, and fill the arrays a[] from the pixels (or, with a
 * NULL and spec given, sum the spectrum of -t s into spec; free it with
 * cr_spectrum_free when this returns 0), with the GIL released but for the
 * signal checks of cr_py_poll. Returns 0; -1 with err set; or -2 when a
 * signal handler raised (its exception is set). */
static int cr_py_trace_frame(const cr_py_job *j, cr_backend *b, char **a, cr_spectrum *spec,
                             cr_err *err)
{
    cr_stack_ops ops = {NULL, cr_py_stack_prepare, cr_py_stack_deliver, NULL,
                        cr_py_stack_progress, NULL};
    cr_py_run r;
    cr_stack st;
    cr_py_wait w;
    int rc;
    w.raised = 0;
    atomic_init(&w.cancel, 0);
    r.j = j;
    r.a = a;
    r.spec = spec;
    r.w = &w;
    ops.ctx = &r;
    w.ts = PyEval_SaveThread();
    rc = cr_stack_init(&st, &ops, 1, j->eval.frame.width, j->eval.frame.height,
                       j->eval.frame.height, NULL, &w.cancel, b, 1, err);
    if (rc == 0) {
        cr_stack_run(&st);
        rc = cr_stack_failed(&st, err) ? -1 : 0;
        cr_stack_free(&st);
    }
    PyEval_RestoreThread(w.ts);
    return w.raised ? -2 : rc;
}

/* _render(scene, is_path, name, config, width, height, frame, frames,
 * backend) -> {name: bytearray} of the arrays above, row-major from the
 * top-left. */
/* Picks the backend of job j (cr_py_backend) and opens it for a width x
 * height frame: the CPU backend's buffer of the frame's pixels, or the GPU
 * session. Refused with MemoryError before anything large is allocated when
 * per_px bytes a pixel cannot fit, as the command line refuses such a run.
 * Returns 0, or -1 with the Python error set and j freed. */
static int cr_py_open(cr_py_job *j, const char *backend, long width, long height, size_t per_px,
                      cr_backend *b)
{
    cr_err err;
    int device = cr_py_backend(backend, &j->cfg);
    if (device == -2) {
        cr_py_job_free(j);
        return -1;
    }
    if (cr_cpu_memory_check((double)width * (double)height * (double)per_px, &err)) {
        cr_py_job_free(j);
        PyErr_Format(PyExc_MemoryError, "a %ldx%ld frame %s; choose a smaller width, height",
                     width, height, err.msg);
        return -1;
    }
    if (cr_backend_open(b, device, cr_backend_cpu_threads(0, j->cfg.cpu_threads), (int)width,
                        (int)height, &err)) {
        cr_py_job_free(j);
        if (device < 0)
            PyErr_NoMemory();
        else
            cr_py_value_error("", &err);
        return -1;
    }
    return 0;
}

static PyObject *cr_py_render(PyObject *self, PyObject *args, PyObject *kw)
{
    const char *scene, *name, *cfg, *backend = "auto";
    Py_ssize_t scene_len, cfg_len;
    int is_path, rc, k;
    long width, height, fk, nf;
    size_t n, per_px;
    cr_py_job j;
    cr_backend b;
    char *ptr[CR_A_N];
    PyObject *out = NULL;
    cr_err err;
    (void)self;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "s#pss#llll|s", render_kw, &scene, &scene_len,
                                     &is_path, &name, &cfg, &cfg_len, &width, &height, &fk, &nf,
                                     &backend))
        return NULL;
    if (cr_py_prepare(&j, scene, scene_len, name, is_path, cfg, cfg_len, width, height, fk, nf))
        return NULL;
    /* the pixels (the CPU's buffer, or the GPU session's pinned one) and the
     * arrays */
    n = (size_t)width * (size_t)height;
    for (per_px = sizeof(cr_pixel), k = 0; k < CR_A_N; k++)
        per_px += cr_py_arrays[k].size;
    if (cr_py_open(&j, backend, width, height, per_px, &b))
        return NULL;
    if (!(out = PyDict_New()))
        goto nomem;
    for (k = 0; k < CR_A_N; k++) {
        PyObject *b = PyByteArray_FromStringAndSize(NULL, (Py_ssize_t)(n * cr_py_arrays[k].size));
        if (!b || PyDict_SetItemString(out, cr_py_arrays[k].name, b)) {
            Py_XDECREF(b);
            goto nomem;
        }
        ptr[k] = PyByteArray_AS_STRING(b);
        Py_DECREF(b); /* the dict holds it */
    }
    err.msg[0] = '\0';
    rc = cr_py_trace_frame(&j, &b, ptr, NULL, &err);
    cr_backend_close(&b);
    cr_py_job_free(&j);
    if (rc) {
        Py_DECREF(out);
        return rc == -2 ? NULL : cr_py_value_error("", &err);
    }
    return out;
nomem:
    cr_backend_close(&b);
    cr_py_job_free(&j);
    Py_XDECREF(out);
    return PyErr_NoMemory();
}

/* The rows of one part of a spectrum (line = 1, the continuum 0) as bytes
 * of n x CR_SPEC_COLS doubles, the values of s_<k>.csv (cr_spectrum_row). */
static PyObject *cr_py_spectrum_rows(const cr_spectrum *s, int line)
{
    int n = line ? s->n_line : s->n_cont;
    double total = cr_spectrum_part_total(s, line);
    PyObject *b = PyBytes_FromStringAndSize(NULL, (Py_ssize_t)((size_t)n * CR_SPEC_COLS *
                                                               sizeof(double)));
    if (!b)
        return NULL;
    for (int i = 0; i < n; i++)
        cr_spectrum_row(s, line, i, total, (double *)PyBytes_AS_STRING(b) + (size_t)i *
                                                                               CR_SPEC_COLS);
    return b;
}

/* _spectrum(scene, is_path, name, config, width, height, frame, frames,
 * backend) -> (line rows, n_line, continuum rows, n_cont, energy_kev, rays,
 * inner_rays, warning or None): the spectrum of -t s (s_<k>.csv) of the
 * frame, traced as render traces it; the rows are bytes of n x CR_SPEC_COLS
 * doubles. The scene's spectrum key (or its defaults) sets the bins. */
static PyObject *cr_py_spectrum(PyObject *self, PyObject *args, PyObject *kw)
{
    const char *scene, *name, *cfg, *backend = "auto";
    Py_ssize_t scene_len, cfg_len;
    int is_path, rc;
    long width, height, fk, nf;
    cr_py_job j;
    cr_backend b;
    cr_spectrum s;
    char note[512];
    PyObject *line = NULL, *cont = NULL;
    cr_err err;
    (void)self;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "s#pss#llll|s", render_kw, &scene, &scene_len,
                                     &is_path, &name, &cfg, &cfg_len, &width, &height, &fk, &nf,
                                     &backend))
        return NULL;
    if (cr_py_prepare(&j, scene, scene_len, name, is_path, cfg, cfg_len, width, height, fk, nf))
        return NULL;
    if (!j.scene.has_disc || j.scene.disc_model != CR_DISC_KEPLERIAN) {
        PyErr_Format(PyExc_ValueError,
                     "scene file %s: accretion: the spectrum is that of a Keplerian disc, and "
                     "the scene has %s; add accretion: {model: keplerian, ...}",
                     name, j.scene.has_disc ? "a chessboard disc" : "no disc");
        cr_py_job_free(&j);
        return NULL;
    }
    if (cr_py_open(&j, backend, width, height, sizeof(cr_pixel), &b))
        return NULL;
    err.msg[0] = '\0';
    memset(&s, 0, sizeof s);
    rc = cr_py_trace_frame(&j, &b, NULL, &s, &err);
    cr_backend_close(&b);
    cr_py_job_free(&j);
    if (rc) {
        cr_spectrum_free(&s);
        return rc == -2 ? NULL : cr_py_value_error("", &err);
    }
    if (!(line = cr_py_spectrum_rows(&s, 1)) || !(cont = cr_py_spectrum_rows(&s, 0))) {
        Py_XDECREF(line);
        cr_spectrum_free(&s);
        return NULL;
    }
    rc = cr_spectrum_coverage_note(&s, note, sizeof note);
    {
        PyObject *out = Py_BuildValue("(NiNidllz)", line, s.n_line, cont, s.n_cont, s.e0,
                                      s.rays, s.inner_rays, rc ? note : NULL);
        cr_spectrum_free(&s);
        return out;
    }
}

/* _backend_info() -> (cuda_built, device or None, why): what backend="auto"
 * chooses with the default configuration, and why not a GPU. */
static PyObject *cr_py_backend_info(PyObject *self, PyObject *unused)
{
    int devices[CR_MAX_GPUS];
    cr_sysconfig cfg;
    cr_err gerr;
    (void)self;
    (void)unused;
    cr_sysconfig_defaults(&cfg);
    if (cr_backend_choose(CR_BACKEND_AUTO, cfg.gpu_enabled, CR_MAX_GPUS, devices, CR_MAX_GPUS,
                          &gerr) > 0)
        return Py_BuildValue("(Nis)", PyBool_FromLong(cr_gpu_built()), devices[0], gerr.msg);
    return Py_BuildValue("(NOs)", PyBool_FromLong(cr_gpu_built()), Py_None, gerr.msg);
}

static char *trace_kw[] = {"scene", "is_path", "name", "config", "width", "height",
                           "frame", "frames", "i", "j", NULL};

/* _trace(..., i, j) -> (bytes of n x CR_PN doubles, n, outcome, hit_r, hit_phi,
 * redshift, steps) */
static PyObject *cr_py_trace(PyObject *self, PyObject *args, PyObject *kw)
{
    const char *scene, *name, *cfg;
    Py_ssize_t scene_len, cfg_len;
    int is_path, rc;
    long width, height, k, n, i, jj;
    cr_py_job j;
    cr_raypath rp;
    cr_err err;
    PyObject *out;
    (void)self;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "s#pss#llllll", trace_kw, &scene, &scene_len,
                                     &is_path, &name, &cfg, &cfg_len, &width, &height, &k, &n,
                                     &i, &jj))
        return NULL;
    if (cr_py_prepare(&j, scene, scene_len, name, is_path, cfg, cfg_len, width, height, k, n))
        return NULL;
    err.msg[0] = '\0';
    if (i < 0 || jj < 0 || i >= width || jj >= height) {
        cr_py_job_free(&j);
        PyErr_Format(PyExc_ValueError,
                     "pixel: (%ld, %ld) is outside the %ldx%ld frame (0 <= i < %ld, 0 <= j < %ld)",
                     i, jj, width, height, width, height);
        return NULL;
    }
    Py_BEGIN_ALLOW_THREADS
    rc = cr_raypath_trace(&j.eval.frame, (int)i, (int)jj, &rp, &err);
    Py_END_ALLOW_THREADS
    cr_py_job_free(&j);
    if (rc)
        return cr_py_value_error("", &err);
    out = Py_BuildValue("(y#lsdddk)", (const char *)rp.pts,
                        (Py_ssize_t)(sizeof(double) * CR_PN * (size_t)rp.n), rp.n,
                        cr_outcome_name(rp.px.outcome), rp.px.hit_r, rp.px.hit_phi,
                        rp.px.redshift, (unsigned long)rp.px.steps);
    cr_raypath_free(&rp);
    return out;
}

/* Outcome names by code (the CSV's words), and the path columns. */
static PyObject *cr_py_constants(PyObject *self, PyObject *unused)
{
    PyObject *names = PyTuple_New(CR_OUT_COUNT_), *settings = PyTuple_New(cr_settings_count);
    int k;
    (void)self;
    (void)unused;
    if (!names || !settings) {
        Py_XDECREF(names);
        Py_XDECREF(settings);
        return NULL;
    }
    for (k = 0; k < cr_settings_count; k++) { /* "section.key" of settings.def */
        char path[96];
        PyObject *s;
        cr_setting_path(&cr_settings[k], path, sizeof path);
        s = PyUnicode_FromString(path);
        if (!s) {
            Py_DECREF(names);
            Py_DECREF(settings);
            return NULL;
        }
        PyTuple_SET_ITEM(settings, k, s);
    }
    for (k = 0; k < CR_OUT_COUNT_; k++) {
        PyObject *s = PyUnicode_FromString(cr_outcome_name(k));
        if (!s) {
            Py_DECREF(names);
            Py_DECREF(settings);
            return NULL;
        }
        PyTuple_SET_ITEM(names, k, s);
    }
    return Py_BuildValue("{s:N,s:N,s:s,s:i,s:s,s:i}", "outcomes", names, "settings", settings,
                         "path_columns", cr_raypath_csv_header, "path_ncol", CR_PN, "version",
                         CURRAY_VERSION, "orbit_max_side", CR_OPIC_MAX_SIDE);
}

/* The rows of a worldline, gathered (worldline.h's emit). */
typedef struct cr_py_rows {
    double *v;
    size_t n, cap; /* rows */
    int nomem;
} cr_py_rows;

static int cr_py_row(void *ctx, const double *row)
{
    cr_py_rows *r = (cr_py_rows *)ctx;
    if (r->n == r->cap) {
        size_t cap = r->cap ? 2 * r->cap : 1024;
        double *v = (double *)realloc(r->v, cap * CR_WL_COLS * sizeof *v);
        if (!v) {
            r->nomem = 1;
            return -1;
        }
        r->v = v;
        r->cap = cap;
    }
    memcpy(r->v + r->n * CR_WL_COLS, row, CR_WL_COLS * sizeof *row);
    r->n++;
    return 0;
}

/* _orbit(text, is_path, name) -> (bytes of n x 12 doubles, n, E, L, K,
 * ended, steps): the worldline of an orbit file (given as text or a path),
 * the rows of curray orbit's CSV; integrated with the GIL released. */
static PyObject *cr_py_orbit(PyObject *self, PyObject *args)
{
    const char *text, *name;
    Py_ssize_t len;
    int is_path, rc;
    cr_particle_spec spec;
    cr_worldline_info info;
    cr_py_rows rows = {NULL, 0, 0, 0};
    cr_err err;
    PyThreadState *ts;
    PyObject *out;
    (void)self;
    if (!PyArg_ParseTuple(args, "s#ps", &text, &len, &is_path, &name))
        return NULL;
    rc = is_path ? cr_particle_spec_load(text, &spec, &err)
                 : cr_particle_spec_load_string(text, (size_t)len, name, &spec, &err);
    if (rc)
        return cr_py_value_error("", &err);
    ts = PyEval_SaveThread();
    rc = cr_worldline_run(&spec, cr_py_row, &rows, &info, &err);
    PyEval_RestoreThread(ts);
    if (rows.nomem) {
        free(rows.v);
        return PyErr_NoMemory();
    }
    if (rc) {
        free(rows.v);
        return cr_py_value_error("", &err);
    }
    out = Py_BuildValue("(y#ndddil)", (const char *)rows.v,
                        (Py_ssize_t)(rows.n * CR_WL_COLS * sizeof(double)), (Py_ssize_t)rows.n,
                        info.E, info.L, info.K, info.ended, info.steps);
    free(rows.v);
    return out;
}

/* The columns of an image of _orbit_picture, those of orbit_image.csv. */
#define CR_PY_OPIC_COLS 8

/* _orbit_picture(text, is_path, name, width, height) -> (bytes of
 * height x width x 3 uint8, bytes of n x 8 doubles (tau, t, order, i, j,
 * t_obs, visible, row), n, points, lost, solves): the lensed picture of an
 * orbit file, curray orbit -t c's orbit.png and orbit_image.csv, by the
 * same code (cr_opic_view_*); traced with the GIL released. */
static PyObject *cr_py_orbit_picture(PyObject *self, PyObject *args)
{
    const char *text, *name;
    Py_ssize_t len;
    int is_path, rc, w, h;
    cr_particle_spec spec;
    cr_worldline_info info;
    cr_opic_view view;
    cr_opic_result r;
    cr_pixel *px = NULL;
    uint8_t *rgb = NULL;
    double *img = NULL;
    cr_err err;
    PyThreadState *ts;
    PyObject *out = NULL;
    long k;
    (void)self;
    if (!PyArg_ParseTuple(args, "s#psii", &text, &len, &is_path, &name, &w, &h))
        return NULL;
    memset(&r, 0, sizeof r);
    rc = is_path ? cr_particle_spec_load(text, &spec, &err)
                 : cr_particle_spec_load_string(text, (size_t)len, name, &spec, &err);
    if (rc)
        return cr_py_value_error("", &err);
    if (cr_opic_view_open(&view, &spec, name, w, h, &err))
        return cr_py_value_error("", &err);
    px = (cr_pixel *)malloc((size_t)w * h * sizeof *px);
    rgb = (uint8_t *)malloc((size_t)w * h * 3);
    if (!px || !rgb) {
        PyErr_NoMemory();
        goto done;
    }
    ts = PyEval_SaveThread();
    /* a failing row sets err itself (the view's err is &err) */
    rc = cr_worldline_run(&spec, cr_opic_view_row, &view, &info, &err);
    if (!rc)
        rc = cr_cpu_render(&view.ev.frame, 0, px, NULL, NULL, NULL, &err) ||
             cr_opic_view_picture(&view, px, rgb, &r, &err);
    PyEval_RestoreThread(ts);
    if (rc) {
        cr_py_value_error("", &err);
        goto done;
    }
    img = (double *)malloc((size_t)(r.n > 0 ? r.n : 1) * CR_PY_OPIC_COLS * sizeof *img);
    if (!img) {
        PyErr_NoMemory();
        goto done;
    }
    for (k = 0; k < r.n; k++) {
        const cr_opic_image *q = &r.img[k];
        double *o = img + k * CR_PY_OPIC_COLS;
        o[0] = q->tau;
        o[1] = q->t;
        o[2] = q->order;
        o[3] = q->i;
        o[4] = q->j;
        o[5] = q->t_obs;
        o[6] = q->visible;
        o[7] = q->row;
    }
    out = Py_BuildValue("(y#y#nnll)", (const char *)rgb, (Py_ssize_t)((size_t)w * h * 3),
                        (const char *)img,
                        (Py_ssize_t)((size_t)r.n * CR_PY_OPIC_COLS * sizeof(double)),
                        (Py_ssize_t)r.n, (Py_ssize_t)view.n, r.lost, r.solves);
done:
    free(img);
    free(px);
    free(rgb);
    cr_opic_result_free(&r);
    cr_opic_view_free(&view);
    return out;
}

static PyMethodDef cr_py_methods[] = {
    {"_orbit_picture", cr_py_orbit_picture, METH_VARARGS,
     "The lensed picture of an orbit file (curray orbit -t c's orbit.png and\n"
     "orbit_image.csv)."},
    {"_orbit", cr_py_orbit, METH_VARARGS,
     "The worldline of an orbit file (curray orbit's rows)."},
    {"_render", (PyCFunction)(void (*)(void))cr_py_render, METH_VARARGS | METH_KEYWORDS,
     "Render one frame; returns a dict of bytearrays (the arrays of render)."},
    {"_spectrum", (PyCFunction)(void (*)(void))cr_py_spectrum, METH_VARARGS | METH_KEYWORDS,
     "The spectrum of one frame (s_<k>.csv's rows)."},
    {"_trace", (PyCFunction)(void (*)(void))cr_py_trace, METH_VARARGS | METH_KEYWORDS,
     "Trace one pixel's ray with its path."},
    {"_constants", cr_py_constants, METH_NOARGS,
     "Outcome names, settings keys, path columns, version."},
    {"_backend_info", cr_py_backend_info, METH_NOARGS,
     "(CUDA built, the GPU backend='auto' would use or None, why not a GPU)."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef cr_py_module = {PyModuleDef_HEAD_INIT, "_curray",
                                          "curray's C library (see curray)", -1, cr_py_methods,
                                          NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__curray(void)
{
    return PyModule_Create(&cr_py_module);
}
