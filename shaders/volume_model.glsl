// Stormlight: the particle model as the GPU holds it, for render/volume/sl_sample_physics.h
// (included right after this text). Tables are float textures read with texelFetch and
// interpolated by the shared functions exactly as on the CPU (hardware filtering would round
// the weights to 8 bits on most GPUs). SL_MAX_FIELDS and SL_MAX_WAVELENGTHS are defined first.
#define SL_GLSL 1
uniform int slNf;
uniform int slMode;
uniform float slXi;
uniform float slAlbedoMean[SL_MAX_FIELDS];
uniform float slAlbedo[SL_MAX_FIELDS * SL_MAX_WAVELENGTHS];
uniform int slMaxOrder[SL_MAX_FIELDS * SL_MAX_WAVELENGTHS];
uniform int slAmsRow[SL_MAX_FIELDS * SL_MAX_WAVELENGTHS]; // first row of table (j, c) in slAms
uniform sampler2D slLogProduct; // texel (k, j * SL_MAX_WAVELENGTHS + c): sum_{i<=k} ln(albedo F_i)
uniform sampler2D slForward;    // texel (k, j * SL_MAX_WAVELENGTHS + c): F_k
uniform sampler2D slAms;        // texel (angle index, slAmsRow[j, c] + k): Ams_k, 1/sr
#define SL_NF slNf
#define SL_NWL SL_MAX_WAVELENGTHS
#define SL_MODE slMode
#define SL_XI slXi
#define SL_ALBEDO_MEAN(j) slAlbedoMean[j]
#define SL_ALBEDO(j, c) slAlbedo[(j) * SL_MAX_WAVELENGTHS + (c)]
#define SL_MAX_ORDER(j, c) slMaxOrder[(j) * SL_MAX_WAVELENGTHS + (c)]
#define SL_LOG_PRODUCT(j, c, k) texelFetch(slLogProduct, ivec2((k), (j) * SL_MAX_WAVELENGTHS + (c)), 0).r
#define SL_FORWARD(j, c, k) texelFetch(slForward, ivec2((k), (j) * SL_MAX_WAVELENGTHS + (c)), 0).r
#define SL_AMS(j, c, k, i) texelFetch(slAms, ivec2((i), slAmsRow[(j) * SL_MAX_WAVELENGTHS + (c)] + (k)), 0).r
#define SL_AMS_PAIR(j, c, k, i, lo, hi) lo = SL_AMS(j, c, k, i); hi = SL_AMS(j, c, k, (i) + 1)
#define SL_MODE_LOW_ALBEDO 0
#define SL_MODE_EQ25 2
