// shaders/display.vert: one triangle that covers the viewport (no vertex buffer: positions from gl_VertexID).
// v_uv is (0,0) at the bottom-left and (1,1) at the top-right of the viewport.
#version 330 core

out vec2 v_uv;

void main() {
    vec2 p = vec2(float((gl_VertexID & 1) << 2), float((gl_VertexID & 2) << 1)) - 1.0;  // (-1,-1) (3,-1) (-1,3)
    v_uv = 0.5 * p + 0.5;
    gl_Position = vec4(p, 0.0, 1.0);
}
