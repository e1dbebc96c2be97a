// Conventions every kernel follows, named once for GLSL and the host: all
// kernels use descriptor set 0 and `layout(local_size_x_id = 0)`, so the host
// picks each kernel's workgroup size through specialisation constant 0. The
// binding indices themselves live beside the data they bind
// (shared/wavefront.h for the stages, shared/bvh.h for the trace kernels).
#ifndef VKPATH_SHARED_BINDINGS_H
#define VKPATH_SHARED_BINDINGS_H

// Specialisation constant ids shared by all kernels.
#define VKP_SPEC_WORKGROUP_SIZE 0
// bool: kernels that read the scene (the BVH and the per-primitive arrays)
// read it through buffer device addresses instead of texel-buffer bindings:
// for scenes whose arrays exceed one binding (shared/bvh_buffers.h).
#define VKP_SPEC_SCENE_BY_ADDRESS 2
// uint: the VKP_FEATURE_* bits a kernel may meet (shared/features.h), bits 0
// to 31 in the first, 32 to 63 in the second.
#define VKP_SPEC_FEATURES 3
#define VKP_SPEC_FEATURES_HIGH 4

#endif  // VKPATH_SHARED_BINDINGS_H
