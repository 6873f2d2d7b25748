//VTK::System::Dec
// Stormlight: draws the HDR background (sky) wherever VTK's opaque geometry left the far plane.
in vec2 texCoord;
uniform sampler2D background;
//VTK::Output::Dec
void main()
{
  gl_FragData[0] = vec4(texture(background, texCoord).rgb, 1.0);
  gl_FragDepth = 1.0;
}
