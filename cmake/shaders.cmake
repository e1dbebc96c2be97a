# Shader compilation: one custom command per shader (glslangValidator with a
# depfile, so editing an included header rebuilds every shader that includes
# it), then one generated C++ source that embeds all the SPIR-V of a group and
# registers it under the shader's file name (without extension).

set(VKPATH_SHADER_INCLUDE_DIR ${CMAKE_SOURCE_DIR}/shaders)

# vkpath_embed_shaders(<target> <registry-name> <shader files...> [TRACING <names...>])
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
function(vkpath_embed_shaders target registry)
    cmake_parse_arguments(PARSE_ARGV 2 EMBED "" "" "TRACING")
    set(spv_files "")
    foreach(src IN LISTS EMBED_UNPARSED_ARGUMENTS)
        get_filename_component(name ${src} NAME_WE)
        set(variants "${name}|")
        if(name IN_LIST EMBED_TRACING)
            list(APPEND variants "${name}_instanced|-DVKP_INSTANCING")
            list(APPEND variants "${name}_rayquery|-DVKP_RAY_QUERY")
        endif()
        foreach(variant IN LISTS variants)
            string(REPLACE "|" ";" parts "${variant}")
            list(GET parts 0 kernel)
            list(LENGTH parts count)
            set(defines "")
            if(count GREATER 1)
                list(GET parts 1 defines)
            endif()
            set(spv ${CMAKE_CURRENT_BINARY_DIR}/spirv/${kernel}.spv)
            set(dep ${CMAKE_CURRENT_BINARY_DIR}/spirv/${kernel}.d)
            add_custom_command(
                OUTPUT ${spv}
                COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_CURRENT_BINARY_DIR}/spirv
                COMMAND ${GLSLANG_VALIDATOR} --quiet --target-env vulkan1.2
                        -I${VKPATH_SHADER_INCLUDE_DIR} -I${CMAKE_CURRENT_SOURCE_DIR} ${defines}
                        --depfile ${dep} -o ${spv} ${src}
                MAIN_DEPENDENCY ${src}
                DEPFILE ${dep}
                COMMENT "glslang ${kernel}.comp"
                VERBATIM)
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
