/* On-disk cache of finished tables, one file per particle type and request.
 *
 * Format (native byte order, which the checksum and the magic's byte-order word guard):
 *   "SLOPTIC\0" | u32 0x01020304 | u32 SL_OPTICS_TABLE_VERSION | u32 key length | key |
 *   u32 table count | per table: 6 doubles (wavelength, sigma_ext, albedo, asymmetry, f,
 *   step_rad), 3 u32 (n_angles, max_order, n_moments), delta[N+1], forward[N+1],
 *   moments[L] (doubles), ams[(N+1) n_angles] (floats) | u64 FNV-1a of everything before.
 * A file is used only if every check passes and its key equals the request's key exactly;
 * anything else is rebuilt and overwritten. Files are written to a temporary name in the
 * same directory and renamed into place. */
#include <errno.h>
#include <fcntl.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#include "optics_internal.h"

static const char MAGIC[8] = {'S', 'L', 'O', 'P', 'T', 'I', 'C', '\0'};

unsigned long long optics_fnv1a(const void *data, size_t n, unsigned long long h)
{
  const unsigned char *p = data;
  for (size_t i = 0; i < n; ++i) {
    h ^= p[i];
    h *= 0x100000001b3ULL;
  }
  return h;
}

int sl_optics_cache_dir(const sl_optics_request *req, char *out, int size, sl_error *err)
{
  const char *dir = req ? req->cache_dir : NULL;
  int n;
  if (dir && *dir)
    n = snprintf(out, (size_t)size, "%s", dir);
  else if ((dir = getenv("SL_CACHE_DIR")) && *dir)
    n = snprintf(out, (size_t)size, "%s", dir);
  else if ((dir = getenv("XDG_CACHE_HOME")) && *dir)
    n = snprintf(out, (size_t)size, "%s/stormlight", dir);
  else if ((dir = getenv("HOME")) && *dir)
    n = snprintf(out, (size_t)size, "%s/.cache/stormlight", dir);
  else
    return sl_fail(err, SL_ERR_ARG, "optics: no cache directory (set SL_CACHE_DIR or HOME)");
  if (n < 0 || n >= size) return sl_fail(err, SL_ERR_ARG, "optics: cache directory path too long");
  return SL_OK;
}

static int make_dirs(const char *path)
{
  char tmp[1024];
  if (snprintf(tmp, sizeof tmp, "%s", path) >= (int)sizeof tmp) return -1;
  for (char *p = tmp + 1; *p; ++p) {
    if (*p != '/') continue;
    *p = '\0';
    if (mkdir(tmp, 0755) != 0 && errno != EEXIST) return -1;
    *p = '/';
  }
  if (mkdir(tmp, 0755) != 0 && errno != EEXIST) return -1;
  return 0;
}

typedef struct writer {
  unsigned char *buf;
  size_t len, cap;
  int failed;
} writer;

static void put(writer *w, const void *data, size_t n)
{
  if (w->failed) return;
  if (w->len + n > w->cap) {
    size_t cap = w->cap ? w->cap : 4096;
    while (cap < w->len + n) cap *= 2;
    unsigned char *b = realloc(w->buf, cap);
    if (!b) {
      w->failed = 1;
      return;
    }
    w->buf = b;
    w->cap = cap;
  }
  memcpy(w->buf + w->len, data, n);
  w->len += n;
}

static void put_u32(writer *w, uint32_t v) { put(w, &v, sizeof v); }

int optics_cache_store(const char *path, const char *key, const sl_phase_table *tables, int n_tables, sl_error *err)
{
  char dir[1024];
  snprintf(dir, sizeof dir, "%s", path);
  char *slash = strrchr(dir, '/');
  if (slash) {
    *slash = '\0';
    if (make_dirs(dir) != 0) return sl_fail(err, SL_ERR_IO, "optics cache: cannot create %s", dir);
  }
  writer w = {0};
  put(&w, MAGIC, sizeof MAGIC);
  put_u32(&w, 0x01020304u);
  put_u32(&w, SL_OPTICS_TABLE_VERSION);
  put_u32(&w, (uint32_t)strlen(key));
  put(&w, key, strlen(key));
  put_u32(&w, (uint32_t)n_tables);
  for (int i = 0; i < n_tables; ++i) {
    const sl_phase_table *t = &tables[i];
    const double head[6] = {t->wavelength_nm, t->sigma_ext, t->albedo, t->asymmetry, t->truncated_fraction, t->step_rad};
    put(&w, head, sizeof head);
    put_u32(&w, (uint32_t)t->n_angles);
    put_u32(&w, (uint32_t)t->max_order);
    put_u32(&w, (uint32_t)t->n_moments);
    const size_t rows = (size_t)t->max_order + 1;
    put(&w, t->delta, sizeof(double) * rows);
    put(&w, t->forward, sizeof(double) * rows);
    put(&w, t->moments, sizeof(double) * (size_t)t->n_moments);
    put(&w, t->ams, sizeof(float) * rows * (size_t)t->n_angles);
  }
  const uint64_t sum = optics_fnv1a(w.buf, w.len, 0xcbf29ce484222325ULL);
  put(&w, &sum, sizeof sum);
  if (w.failed) {
    free(w.buf);
    return sl_fail(err, SL_ERR_NOMEM, "optics cache: out of memory");
  }
  char tmp[1100];
  snprintf(tmp, sizeof tmp, "%s.XXXXXX", path);
  const int fd = mkstemp(tmp);
  if (fd < 0) {
    free(w.buf);
    return sl_fail(err, SL_ERR_IO, "optics cache: cannot create a file beside %s", path);
  }
  FILE *f = fdopen(fd, "wb");
  int ok = f && fwrite(w.buf, 1, w.len, f) == w.len;
  if (f) ok = (fclose(f) == 0) && ok;
  else close(fd);
  free(w.buf);
  if (!ok || rename(tmp, path) != 0) {
    unlink(tmp);
    return sl_fail(err, SL_ERR_IO, "optics cache: cannot write %s", path);
  }
  return SL_OK;
}

typedef struct reader {
  const unsigned char *p, *end;
  int bad;
} reader;

static void get(reader *r, void *out, size_t n)
{
  if (r->bad || (size_t)(r->end - r->p) < n) {
    r->bad = 1;
    memset(out, 0, n);
    return;
  }
  memcpy(out, r->p, n);
  r->p += n;
}

static uint32_t get_u32(reader *r)
{
  uint32_t v;
  get(r, &v, sizeof v);
  return v;
}

int optics_cache_load(const char *path, const char *key, sl_phase_table *tables, int n_tables, sl_error *err)
{
  FILE *f = fopen(path, "rb");
  if (!f) return sl_fail(err, SL_ERR_IO, "optics cache: no file %s", path);
  unsigned char *buf = NULL;
  size_t len = 0, cap = 0;
  for (;;) {
    if (len == cap) {
      cap = cap ? 2 * cap : 1 << 20;
      unsigned char *b = realloc(buf, cap);
      if (!b) {
        free(buf);
        fclose(f);
        return sl_fail(err, SL_ERR_NOMEM, "optics cache: out of memory");
      }
      buf = b;
    }
    const size_t got = fread(buf + len, 1, cap - len, f);
    len += got;
    if (got == 0) break;
  }
  fclose(f);
  int status = SL_ERR_FORMAT;
  uint64_t stored;
  if (len < sizeof MAGIC + 16 + sizeof stored) goto done;
  memcpy(&stored, buf + len - sizeof stored, sizeof stored);
  if (optics_fnv1a(buf, len - sizeof stored, 0xcbf29ce484222325ULL) != stored) goto done;
  reader r = {buf, buf + len - sizeof stored, 0};
  char magic[8];
  get(&r, magic, sizeof magic);
  if (memcmp(magic, MAGIC, sizeof MAGIC) != 0 || get_u32(&r) != 0x01020304u ||
      get_u32(&r) != SL_OPTICS_TABLE_VERSION)
    goto done;
  const uint32_t key_len = get_u32(&r);
  if (r.bad || key_len != strlen(key) || (size_t)(r.end - r.p) < key_len || memcmp(r.p, key, key_len) != 0) goto done;
  r.p += key_len;
  if (get_u32(&r) != (uint32_t)n_tables) goto done;
  for (int i = 0; i < n_tables && !r.bad; ++i) {
    double head[6];
    get(&r, head, sizeof head);
    const uint32_t n_angles = get_u32(&r), max_order = get_u32(&r), n_moments = get_u32(&r);
    if (r.bad || n_angles < 3 || n_angles > 2000001 || max_order < 1 || max_order > SL_OPTICS_MAX_ORDER ||
        n_moments < 2 || n_moments > 100000)
      goto fail_tables;
    sl_phase_table *t = &tables[i];
    if (!optics_table_alloc(t, (int)max_order, (int)n_angles, (int)n_moments)) {
      status = SL_ERR_NOMEM;
      goto fail_tables;
    }
    t->wavelength_nm = head[0];
    t->sigma_ext = head[1];
    t->albedo = head[2];
    t->asymmetry = head[3];
    t->truncated_fraction = head[4];
    t->step_rad = head[5];
    t->inv_step_rad = 1.0 / head[5];
    const size_t rows = (size_t)max_order + 1;
    get(&r, (void *)t->delta, sizeof(double) * rows);
    get(&r, (void *)t->forward, sizeof(double) * rows);
    get(&r, (void *)t->moments, sizeof(double) * n_moments);
    get(&r, (void *)t->ams, sizeof(float) * rows * n_angles);
  }
  if (r.bad || r.p != r.end) goto fail_tables;
  status = SL_OK;
  goto done;
fail_tables:
  for (int i = 0; i < n_tables; ++i) optics_table_release(&tables[i]);
done:
  free(buf);
  if (status != SL_OK) return sl_fail(err, status, "optics cache: %s is stale or corrupt", path);
  return SL_OK;
}

int optics_cache_lock(const char *path)
{
  char dir[1024], lock[1100];
  snprintf(dir, sizeof dir, "%s", path);
  char *slash = strrchr(dir, '/');
  if (slash) {
    *slash = '\0';
    if (make_dirs(dir) != 0) return -1;
  }
  snprintf(lock, sizeof lock, "%s.lock", path);
  const int fd = open(lock, O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) return -1;
  /* A POSIX record lock (it works over NFS, where flock may not), released by the kernel if the
   * process dies while it builds. The lock file stays: removing it would race with a waiter. */
  struct flock whole = {.l_type = F_WRLCK, .l_whence = SEEK_SET, .l_start = 0, .l_len = 0};
  int rc;
  while ((rc = fcntl(fd, F_SETLKW, &whole)) != 0 && errno == EINTR) {
  }
  if (rc != 0) {
    close(fd);
    return -1;
  }
  return fd;
}

void optics_cache_unlock(int fd)
{
  if (fd >= 0) close(fd); /* closing releases the process's locks on the file */
}
