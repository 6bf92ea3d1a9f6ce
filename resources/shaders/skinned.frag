#version 330 core
// Two-sided Lambert: the colour is the tint scaled by the light, so its hue stays the tint's
// (the crowd's level tints are told apart by hue).
in vec3 vNormal;
in vec4 vTint;
uniform vec3 uLightDirection; // towards the light, unit
uniform float uAlpha;
out vec4 fragColor;

void main() {
  float len = length(vNormal);
  vec3 n = len > 0.0 ? vNormal / len : vec3(0.0, 1.0, 0.0);
  float diffuse = abs(dot(n, uLightDirection));
  fragColor = vec4(vTint.rgb * (0.35 + 0.65 * diffuse), uAlpha * vTint.a);
}
