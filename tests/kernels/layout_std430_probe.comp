// A struct whose std430 layout differs from its scalar layout; the layout
// test checks that reflection reports the std430 padding (so it would catch
// a shared struct declared without `scalar`).
#version 460

layout(local_size_x = 1) in;

struct ThreeVec3FourUint {
    vec3 a;
    vec3 b;
    vec3 c;
    uint d;
    uint e;
    uint f;
    uint g;
};

layout(binding = 0, std430) buffer Items { ThreeVec3FourUint items[]; };

void main() { items[0] = items[1]; }
