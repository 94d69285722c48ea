/* curray._curray: the C side of the Python package (python/README section of
 * the top README). It calls the same library as the command line: the scene
 * and configuration loaders (src/io), the CPU backend (src/cpu) and the core
 * trace loop (src/core, with its path recorder for trace()). Every failure
 * comes back as a cr_err message and is raised as ValueError (bad input) or
 * MemoryError; nothing here exits or prints.
 *
 * The pixels come back as one bytes-like buffer of cr_pixel structs; the
 * Python side views its fields through pixel_layout() (offsets from
 * offsetof, so a new field in cr_pixel cannot shift them silently). */
#define PY_SSIZE_T_CLEAN
#include <Python.h>

#include <stddef.h>
#include <stdlib.h>
#include <string.h>

#include "cli/cli.h"
#include "cpu/render_cpu.h"
#include "io/info.h"
#include "io/raypath.h"
#include "io/scene.h"
#include "io/sysconfig.h"

/* One frame ready to trace: the loaded scene, the settings and the frame. */
typedef struct cr_py_job {
    cr_scene scene;
    int scene_loaded;
    cr_sysconfig cfg;
    cr_sphere *spheres;
    cr_frame f;
} cr_py_job;

static void cr_py_job_free(cr_py_job *j)
{
    if (j->scene_loaded)
        cr_scene_free(&j->scene);
    free(j->spheres);
    j->spheres = NULL;
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
    j->spheres = malloc(sizeof *j->spheres * (size_t)(j->scene.n_spheres + 1));
    if (!j->spheres) {
        cr_py_job_free(j);
        PyErr_NoMemory();
        return -1;
    }
    ts.integrator = j->cfg.integrator;
    ts.tolerance = j->cfg.tolerance;
    ts.step_multiplier = j->cfg.step_multiplier;
    ts.horizon_epsilon = j->cfg.horizon_epsilon;
    ts.max_steps = j->cfg.max_steps;
    ts.max_turns = j->cfg.max_turns;
    ts.samples = j->cfg.samples;
    if (cr_scene_frame(&j->scene, (int)k, (int)n, (int)width, (int)height, &ts, &j->f,
                       j->spheres, &err)) {
        cr_py_job_free(j);
        cr_py_value_error("scene file ", &err);
        return -1;
    }
    return 0;
}

static char *render_kw[] = {"scene", "is_path", "name", "config", "width", "height",
                            "frame", "frames", NULL};

/* _render(scene, is_path, name, config, width, height, frame, frames)
 * -> bytearray of width*height cr_pixel, row-major from the top-left. */
static PyObject *cr_py_render(PyObject *self, PyObject *args, PyObject *kw)
{
    const char *scene, *name, *cfg;
    Py_ssize_t scene_len, cfg_len;
    int is_path;
    long width, height, k, n;
    cr_py_job j;
    PyObject *buf;
    cr_err err;
    int rc;
    (void)self;
    if (!PyArg_ParseTupleAndKeywords(args, kw, "s#pss#llll", render_kw, &scene, &scene_len,
                                     &is_path, &name, &cfg, &cfg_len, &width, &height, &k, &n))
        return NULL;
    if (cr_py_prepare(&j, scene, scene_len, name, is_path, cfg, cfg_len, width, height, k, n))
        return NULL;
    buf = PyByteArray_FromStringAndSize(NULL, (Py_ssize_t)(sizeof(cr_pixel) * (size_t)width *
                                                           (size_t)height));
    if (!buf) {
        cr_py_job_free(&j);
        return NULL;
    }
    err.msg[0] = '\0';
    {
        cr_pixel *px = (cr_pixel *)PyByteArray_AS_STRING(buf);
        int threads = j.cfg.cpu_threads; /* 0: every core */
        Py_BEGIN_ALLOW_THREADS
        rc = cr_cpu_render(&j.f, threads, px, NULL, NULL, NULL, &err);
        Py_END_ALLOW_THREADS
    }
    cr_py_job_free(&j);
    if (rc) {
        Py_DECREF(buf);
        return cr_py_value_error("", &err);
    }
    return buf;
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
    rc = cr_raypath_trace(&j.f, (int)i, (int)jj, &rp, &err);
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

/* Field offsets of cr_pixel for the NumPy view. */
static PyObject *cr_py_pixel_layout(PyObject *self, PyObject *unused)
{
    (void)self;
    (void)unused;
    return Py_BuildValue("{s:n,s:n,s:n,s:n,s:n,s:n,s:n,s:n,s:n,s:n,s:n}", "itemsize",
                         (Py_ssize_t)sizeof(cr_pixel), "redshift",
                         (Py_ssize_t)offsetof(cr_pixel, redshift), "err_mean",
                         (Py_ssize_t)offsetof(cr_pixel, err_mean), "err_std",
                         (Py_ssize_t)offsetof(cr_pixel, err_std), "hit_r",
                         (Py_ssize_t)offsetof(cr_pixel, hit_r), "hit_phi",
                         (Py_ssize_t)offsetof(cr_pixel, hit_phi), "bolo",
                         (Py_ssize_t)offsetof(cr_pixel, bolo), "steps",
                         (Py_ssize_t)offsetof(cr_pixel, steps), "object",
                         (Py_ssize_t)offsetof(cr_pixel, object), "outcome",
                         (Py_ssize_t)offsetof(cr_pixel, outcome), "color",
                         (Py_ssize_t)offsetof(cr_pixel, color));
}

/* Outcome names by code (the CSV's words), and the path columns. */
static PyObject *cr_py_constants(PyObject *self, PyObject *unused)
{
    PyObject *names = PyTuple_New(CR_OUT_COUNT_);
    int k;
    (void)self;
    (void)unused;
    if (!names)
        return NULL;
    for (k = 0; k < CR_OUT_COUNT_; k++) {
        PyObject *s = PyUnicode_FromString(cr_outcome_name(k));
        if (!s) {
            Py_DECREF(names);
            return NULL;
        }
        PyTuple_SET_ITEM(names, k, s);
    }
    return Py_BuildValue("{s:N,s:s,s:i,s:s}", "outcomes", names, "path_columns",
                         cr_raypath_csv_header, "path_ncol", CR_PN, "version", CURRAY_VERSION);
}

static PyMethodDef cr_py_methods[] = {
    {"_render", (PyCFunction)(void (*)(void))cr_py_render, METH_VARARGS | METH_KEYWORDS,
     "Render one frame; returns a bytearray of cr_pixel."},
    {"_trace", (PyCFunction)(void (*)(void))cr_py_trace, METH_VARARGS | METH_KEYWORDS,
     "Trace one pixel's ray with its path."},
    {"_pixel_layout", cr_py_pixel_layout, METH_NOARGS, "cr_pixel field offsets."},
    {"_constants", cr_py_constants, METH_NOARGS, "Outcome names, path columns, version."},
    {NULL, NULL, 0, NULL}};

static struct PyModuleDef cr_py_module = {PyModuleDef_HEAD_INIT, "_curray",
                                          "curray's C library (see curray)", -1, cr_py_methods,
                                          NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__curray(void)
{
    return PyModule_Create(&cr_py_module);
}
