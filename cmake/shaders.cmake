# Shader compilation: one custom command per shader (glslangValidator with a
# depfile, so editing an included header rebuilds every shader that includes
# it), then one generated C++ source that embeds all the SPIR-V of a group and
# registers it under the shader's file name (without extension).

set(VKPATH_SHADER_INCLUDE_DIR ${CMAKE_SOURCE_DIR}/shaders)

# The feature profiles' keys (shaders/shared/feature_profiles.h, the lines of
# VKP_FEATURE_PROFILES) and their mask macros, in the header's order.
file(STRINGS ${VKPATH_SHADER_INCLUDE_DIR}/shared/feature_profiles.h VKPATH_PROFILE_LINES
     REGEX "^ *X\\([A-Z_]+, [a-z_]+, \"")
# (The lines' continuation backslashes would escape the list's semicolons.)
string(REPLACE "\\" "" VKPATH_PROFILE_LINES "${VKPATH_PROFILE_LINES}")
set(VKPATH_FEATURE_PROFILES "")
foreach(line IN LISTS VKPATH_PROFILE_LINES)
    string(REGEX REPLACE "^ *X\\(([A-Z_]+), ([a-z_]+),.*" "\\2|-DVKP_PROFILE_FEATURES=VKP_FEATURE_PROFILE_\\1"
           profile "${line}")
    list(APPEND VKPATH_FEATURE_PROFILES "${profile}")
endforeach()
set_property(DIRECTORY ${CMAKE_SOURCE_DIR} APPEND PROPERTY CMAKE_CONFIGURE_DEPENDS
             ${VKPATH_SHADER_INCLUDE_DIR}/shared/feature_profiles.h)
if(NOT VKPATH_FEATURE_PROFILES)
    message(FATAL_ERROR "no feature profiles found in shaders/shared/feature_profiles.h")
endif()

# What the build's spirv-opt does to a profiled kernel: inline every call,
# then twice fold and remove the branches that the profile's constant-false
# feature tests (shared/features.h hasFeature) leave and the code only they
# reached (a third time finds nothing). Nothing reassociates or contracts
# floating-point arithmetic: images are the same bit for bit as from
# glslang's modules (docs/BENCHMARKS.md, "Start-up", which also has what it
# saves). 3 s for the megakernel's smooth build, 6 s for its core one.
set(VKPATH_SPIRV_CLEANUP --eliminate-dead-branches --simplify-instructions --ccp
    --eliminate-dead-branches --eliminate-dead-code-aggressive --eliminate-dead-functions)
set(VKPATH_SPIRV_PROFILE_PASSES --merge-return --inline-entry-points-exhaustive
    --eliminate-dead-functions --eliminate-local-single-block --eliminate-local-single-store
    --ssa-rewrite ${VKPATH_SPIRV_CLEANUP} ${VKPATH_SPIRV_CLEANUP})

# vkpath_embed_shaders(<target> <registry-name> <shader files...>
#                      [TRACING <names...>] [PROFILED <names...>])
# Creates a static library <target> whose single generated source defines
# vkpath::shaders::<registry-name>() returning the embedded kernels. The
# kernels named after TRACING (file names without extension) trace rays and
# are compiled twice more:
#   <name>_instanced, with VKP_INSTANCING: the traversal that enters instances'
#     trees (shaders/shared/bvh_traverse.h), which kernels of scenes without
#     instances do not carry (its code would cost them pipeline compile time
#     and memory even where specialisation removes it);
#   <name>_rayquery, with VKP_RAY_QUERY: tracing by the device's acceleration
#     structures (shaders/shared/bvh_ray_query.h), whose SPIR-V capability only
#     a device with ray queries accepts.
# The kernels named after PROFILED are compiled, each of those variants, once
# more per feature profile (<variant>_<key>, shared/feature_profiles.h), and
# those builds go through spirv-opt (VKPATH_SPIRV_PROFILE_PASSES). The general
# builds do not: with nothing to remove, lavapipe took longer over the inlined
# module (3.3 s against 2.0 s for assets/material_extensions.gltf's pipelines).
# A variant's text, "KERNEL|DEFINES|profile" (the defines and the third part,
# which marks a feature profile's build, may be left out), into its kernel
# name, its glslang defines and whether it is a profile's build.
function(vkpath_variant_parts variant out_kernel out_defines out_profiled)
    string(REPLACE "|" ";" parts "${variant}")
    list(GET parts 0 kernel)
    list(LENGTH parts count)
    set(defines "")
    if(count GREATER 1)
        list(GET parts 1 defines)
    endif()
    set(profiled FALSE)
    if(count GREATER 2)
        set(profiled TRUE)
    endif()
    set(${out_kernel} "${kernel}" PARENT_SCOPE)
    set(${out_defines} "${defines}" PARENT_SCOPE)
    set(${out_profiled} ${profiled} PARENT_SCOPE)
endfunction()

function(vkpath_embed_shaders target registry)
    cmake_parse_arguments(PARSE_ARGV 2 EMBED "" "" "TRACING;PROFILED")
    set(spv_files "")
    foreach(src IN LISTS EMBED_UNPARSED_ARGUMENTS)
        get_filename_component(name ${src} NAME_WE)
        set(traversals "${name}|")
        if(name IN_LIST EMBED_TRACING)
            list(APPEND traversals "${name}_instanced|-DVKP_INSTANCING")
            list(APPEND traversals "${name}_rayquery|-DVKP_RAY_QUERY")
        endif()
        set(variants "")
        foreach(traversal IN LISTS traversals)
            list(APPEND variants "${traversal}")
            if(name IN_LIST EMBED_PROFILED)
                vkpath_variant_parts("${traversal}" base base_defines unused)
                foreach(profile IN LISTS VKPATH_FEATURE_PROFILES)
                    string(REPLACE "|" ";" profile_parts "${profile}")
                    list(GET profile_parts 0 key)
                    list(GET profile_parts 1 define)
                    list(APPEND variants "${base}_${key}|${base_defines} ${define}|profile")
                endforeach()
            endif()
        endforeach()
        foreach(variant IN LISTS variants)
            vkpath_variant_parts("${variant}" kernel defines profiled)
            separate_arguments(defines UNIX_COMMAND "${defines}")
            set(spv ${CMAKE_CURRENT_BINARY_DIR}/spirv/${kernel}.spv)
            set(dep ${CMAKE_CURRENT_BINARY_DIR}/spirv/${kernel}.d)
            set(compiled ${spv})
            if(profiled)
                set(compiled ${CMAKE_CURRENT_BINARY_DIR}/spirv/${kernel}.glslang.spv)
            endif()
            add_custom_command(
                OUTPUT ${compiled}
                COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_CURRENT_BINARY_DIR}/spirv
                COMMAND ${GLSLANG_VALIDATOR} --quiet --target-env vulkan1.2
                        -I${VKPATH_SHADER_INCLUDE_DIR} -I${CMAKE_CURRENT_SOURCE_DIR} ${defines}
                        --depfile ${dep} -o ${compiled} ${src}
                MAIN_DEPENDENCY ${src}
                DEPFILE ${dep}
                COMMENT "glslang ${kernel}.comp"
                VERBATIM)
            if(profiled)
                add_custom_command(
                    OUTPUT ${spv}
                    COMMAND ${SPIRV_OPT} --target-env=vulkan1.2 --scalar-block-layout
                            ${VKPATH_SPIRV_PROFILE_PASSES} -o ${spv} ${compiled}
                    DEPENDS ${compiled}
                    COMMENT "spirv-opt ${kernel}"
                    VERBATIM)
            endif()
            list(APPEND spv_files ${spv})
        endforeach()
    endforeach()

    set(generated ${CMAKE_CURRENT_BINARY_DIR}/${target}_embedded.cpp)
    add_custom_command(
        OUTPUT ${generated}
        COMMAND ${CMAKE_COMMAND} -DOUTPUT=${generated} -DREGISTRY=${registry}
                "-DSPIRV_FILES=${spv_files}" -P ${CMAKE_SOURCE_DIR}/cmake/embed_spirv.cmake
        DEPENDS ${spv_files} ${CMAKE_SOURCE_DIR}/cmake/embed_spirv.cmake
        COMMENT "embed SPIR-V (${registry})"
        VERBATIM)
    add_library(${target} STATIC ${generated})
    target_include_directories(${target} PUBLIC ${CMAKE_SOURCE_DIR}/host)
endfunction()
