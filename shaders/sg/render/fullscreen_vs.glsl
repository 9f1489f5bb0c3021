// Vertex program of a full-screen pass: one triangle covering the viewport,
// with no vertex attributes. Draw it as 3 vertices with an empty vertex
// array object bound (glDrawArrays(GL_TRIANGLES, 0, 3)): vertex
// gl_VertexID = 0, 1, 2 lands at clip (-1, -1), (3, -1), (-1, 3).
// vScreenUv is the position in the viewport, [0, 1]^2 over it ((0, 0) at
// the bottom left): the texture coordinates of an image that fills the
// viewport. The viewer's display pass and the benchmarks' fragment passes
// run on it.
// glsl-targets: glsl330 es300 (besides GLSL 4.50; not Vulkan GLSL, which
// spells gl_VertexID as gl_VertexIndex)
out vec2 vScreenUv;

void main() {
    vec2 p = vec2(float((gl_VertexID << 1) & 2), float(gl_VertexID & 2));
    vScreenUv = p;
    gl_Position = vec4(2.0 * p - 1.0, 0.0, 1.0);
}
