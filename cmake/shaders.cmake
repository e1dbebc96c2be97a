# Shader compilation: one custom command per shader (glslangValidator with a
# depfile, so editing an included header rebuilds every shader that includes
# it), then one generated C++ source that embeds all the SPIR-V of a group and
# registers it under the shader's file name (without extension).

set(VKPATH_SHADER_INCLUDE_DIR ${CMAKE_SOURCE_DIR}/shaders)

# vkpath_embed_shaders(<target> <registry-name> <shader files...>)
# Creates a static library <target> whose single generated source defines
# vkpath::shaders::<registry-name>() returning the embedded kernels.
function(vkpath_embed_shaders target registry)
    set(spv_files "")
    foreach(src IN LISTS ARGN)
        get_filename_component(name ${src} NAME_WE)
        set(spv ${CMAKE_CURRENT_BINARY_DIR}/spirv/${name}.spv)
        set(dep ${CMAKE_CURRENT_BINARY_DIR}/spirv/${name}.d)
        add_custom_command(
            OUTPUT ${spv}
            COMMAND ${CMAKE_COMMAND} -E make_directory ${CMAKE_CURRENT_BINARY_DIR}/spirv
            COMMAND ${GLSLANG_VALIDATOR} --quiet --target-env vulkan1.2
                    -I${VKPATH_SHADER_INCLUDE_DIR} -I${CMAKE_CURRENT_SOURCE_DIR}
                    --depfile ${dep} -o ${spv} ${src}
            MAIN_DEPENDENCY ${src}
            DEPFILE ${dep}
            COMMENT "glslang ${name}.comp"
            VERBATIM)
        list(APPEND spv_files ${spv})
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
