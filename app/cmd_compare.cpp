// stormlight compare: the regression metric offered to users.
#include <cjson/cJSON.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "cli.h"
#include "commands.h"
#include "sl_image_io.h"

int sl_cmd_compare(int argc, char **argv)
{
  sl::Options o("compare", "A.exr B.exr [--threshold R] [--json] [--diff diff.png]",
                "Compares image A with reference B on linear HDR RGB: relative RMSE, maximum absolute\n"
                "difference and PSNR. Exits 1 when the relative RMSE exceeds the threshold.");
  o.option("threshold", "R", "largest relative RMSE that passes", "0.01");
  o.option("diff", "FILE.png", "write a false-colour map of |A-B| (black, red, yellow, white = largest)");
  o.flag("json", "print one JSON object");
  const int early = sl::parse_or_exit(o, argc, argv);
  if (early >= 0) return early;
  if (o.positional().size() != 2) return sl::fail("compare", "give two EXR files A and B", 2);
  double threshold;
  if (!o.number("threshold", &threshold) || threshold < 0) return sl::fail("compare", "--threshold must be >= 0", 2);
  sl_error err{};
  sl_image a{}, b{};
  if (sl_read_exr(o.positional()[0].c_str(), &a, &err) || sl_read_exr(o.positional()[1].c_str(), &b, &err)) {
    sl_image_free(&a);
    return sl::fail("compare", err.message);
  }
  sl_image_metrics m;
  if (sl_image_compare(&a, &b, &m, &err)) {
    sl_image_free(&a);
    sl_image_free(&b);
    return sl::fail("compare", o.positional()[0] + " vs " + o.positional()[1] + ": " + err.message);
  }
  int rc = 0;
  if (o.has("diff")) {
    std::vector<unsigned char> rgb((size_t)a.width * a.height * 3);
    sl_image_diff_rgb8(&a, &b, 0.0, rgb.data());
    if (sl_write_png_rgb8(o.str("diff").c_str(), a.width, a.height, rgb.data(), &err))
      rc = sl::fail("compare", err.message);
  }
  const bool pass = m.nonfinite == 0 && m.relative_rmse <= threshold;
  if (o.has("json")) {
    cJSON *root = cJSON_CreateObject();
    cJSON_AddNumberToObject(root, "relative_rmse", m.relative_rmse);
    cJSON_AddNumberToObject(root, "max_abs_diff", m.max_abs_diff);
    if (std::isfinite(m.psnr_db)) cJSON_AddNumberToObject(root, "psnr_db", m.psnr_db);
    else cJSON_AddNullToObject(root, "psnr_db");
    cJSON_AddNumberToObject(root, "nonfinite_pixels", (double)m.nonfinite);
    cJSON_AddNumberToObject(root, "threshold", threshold);
    cJSON_AddBoolToObject(root, "pass", pass);
    char *text = cJSON_PrintUnformatted(root);
    std::printf("%s\n", text);
    std::free(text);
    cJSON_Delete(root);
  } else {
    std::printf("relative RMSE %.6g (threshold %g)  max |diff| %.6g  PSNR %.2f dB  non-finite %ld  -> %s\n",
                m.relative_rmse, threshold, m.max_abs_diff, m.psnr_db, m.nonfinite, pass ? "pass" : "FAIL");
  }
  sl_image_free(&a);
  sl_image_free(&b);
  if (rc) return rc;
  return pass ? 0 : 1;
}
