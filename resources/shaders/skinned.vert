#version 330 core
// Linear blend skinning on the GPU (runtime/skinning_job.h does the same on the CPU):
// p' = (sum_i w_i P[j_i]) (p, 1). The palettes of every instance of a draw sit in one
// RGBA32F texture, three texels (the matrix's first three rows) per joint, instance after
// instance from uPaletteBase, wrapped at the texture's width (GL 3.3 core has no SSBO).
layout(location = 0) in vec3 aPosition;   // cm, bind pose
layout(location = 1) in vec3 aNormal;
layout(location = 2) in uvec4 aJoints;
layout(location = 3) in vec4 aWeights;
layout(location = 4) in vec4 iPlacement;  // per instance: ground position (cm), yaw (radians)
layout(location = 5) in vec4 iTint;       // per instance: colour

uniform mat4 uViewProjection;
uniform sampler2D uPalettes;
uniform int uPaletteBase;   // texel of this draw's first instance
uniform int uJointCount;
uniform int uTextureWidth;

out vec3 vNormal;
out vec4 vTint;

vec4 texel(int index) {
  return texelFetch(uPalettes, ivec2(index % uTextureWidth, index / uTextureWidth), 0);
}

void main() {
  int first = uPaletteBase + gl_InstanceID * uJointCount * 3;
  vec4 r0 = vec4(0.0), r1 = vec4(0.0), r2 = vec4(0.0);
  for (int i = 0; i < 4; ++i) {
    float w = aWeights[i];
    if (w == 0.0)
      continue;
    int t = first + int(aJoints[i]) * 3;
    r0 += w * texel(t);
    r1 += w * texel(t + 1);
    r2 += w * texel(t + 2);
  }
  vec4 p = vec4(aPosition, 1.0);
  vec3 skinned = vec3(dot(r0, p), dot(r1, p), dot(r2, p));
  vec3 normal = vec3(dot(r0.xyz, aNormal), dot(r1.xyz, aNormal), dot(r2.xyz, aNormal));
  float c = cos(iPlacement.w), s = sin(iPlacement.w);
  mat3 yaw = mat3(c, 0.0, -s, 0.0, 1.0, 0.0, s, 0.0, c);
  vec3 world = yaw * skinned + iPlacement.xyz;
  vNormal = yaw * normal;
  vTint = iTint;
  gl_Position = uViewProjection * vec4(world, 1.0);
}
