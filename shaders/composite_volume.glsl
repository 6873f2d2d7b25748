//VTK::System::Dec
// Stormlight: composites the premultiplied HDR volume layer over what is already drawn
// (background and VTK geometry), at the volume's opacity-weighted depth so that geometry in
// front of the cloud hides it. Blending is GL_ONE, GL_ONE_MINUS_SRC_ALPHA (premultiplied "over").
in vec2 texCoord;
uniform sampler2D volumeColor;  // premultiplied radiance, alpha = 1 - transparency
uniform sampler2D volumeDepth;  // view-axis distance, +inf where empty
uniform float nearPlane;
uniform float farPlane;
//VTK::Output::Dec
void main()
{
  vec4 c = texture(volumeColor, texCoord);
  float z = texture(volumeDepth, texCoord).r;
  // Perspective depth of view-axis distance z, mapped to [0, 1].
  float ndc = (farPlane + nearPlane) / (farPlane - nearPlane) - 2.0 * farPlane * nearPlane / ((farPlane - nearPlane) * z);
  gl_FragDepth = (isinf(z) || z >= farPlane) ? 1.0 : clamp(0.5 * ndc + 0.5, 0.0, 1.0);
  gl_FragData[0] = c;
}
