// Vertex shader of the engine-integration sample. Nothing bump-specific
// happens here: no tangents are needed (the fragment shader builds the frame
// per pixel, Mikkelsen 2019 listing 6). The one requirement of the surfgrad
// prologue (listing 16) is that positions reach the fragment shader
// RELATIVE TO THE CAMERA, so screen derivatives carry no large translation.
layout(location = 0) in vec3 aPosition; // object space
layout(location = 1) in vec3 aNormal;   // object space
layout(location = 2) in vec2 aUv0;

uniform mat4 uModel;       // object -> world
uniform mat3 uNormalMat;   // object normal -> world normal (inverse transpose)
uniform vec3 uCameraPos;   // world
uniform mat4 uViewProjRel; // camera-relative world -> clip (view rotation + projection)

out vec3 vRelPos; // world position minus camera position
out vec3 vNormal; // world normal, interpolated, NOT renormalized here
out vec2 vUv0;

void main() {
    vec3 worldPos = (uModel * vec4(aPosition, 1.0)).xyz;
    vRelPos = worldPos - uCameraPos;
    vNormal = uNormalMat * aNormal;
    vUv0 = aUv0;
    gl_Position = uViewProjRel * vec4(vRelPos, 1.0);
}
