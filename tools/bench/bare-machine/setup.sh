# Sourced from the repository root on the bare GPU machine (see pack): unpacks
# .devbundle/bundle.tar.xz into $VKB_PREFIX and writes build/vkpath, build/vkpath-base and
# build/tests/vkpath_tests as wrappers that run the carried binaries through the carried
# loader. The tests look for the checkout at the folder they were compiled in (pack records it
# in the bundle as built-at): where that folder is absent it becomes a link to this checkout.
# The assignment's scenes travel in the bundle, and VKPATH_SCENES_DIR points the tests there.
# Refuses to run over a real build.
#
# Environment (all optional):
#   VKB_PREFIX  where the bundle is unpacked (default: .devbundle/root in this checkout)
#   NVIDIA_DIR  the machine's NVIDIA driver, with lib64/, lib/ and share/vulkan/icd.d/
#               (default: /usr/local/nvidia, where NVIDIA's container runtime mounts it)
VKB_PREFIX=${VKB_PREFIX:-$(pwd)/.devbundle/root}
NVIDIA_DIR=${NVIDIA_DIR:-/usr/local/nvidia}
if [ -f build/vkpath ] && ! grep -q "$VKB_PREFIX" build/vkpath 2>/dev/null; then
    echo "setup.sh: build/vkpath is a real build here; this is for the bare machine" >&2
    return 1 2>/dev/null || exit 1
fi
mkdir -p "$VKB_PREFIX"
python3 -c "import sys, tarfile; tarfile.open('.devbundle/bundle.tar.xz').extractall(sys.argv[1])" "$VKB_PREFIX"
sed -i "s|@VKB_PREFIX@|$VKB_PREFIX|" "$VKB_PREFIX/layers/VkLayer_khronos_validation.json"
built_at=$(cat "$VKB_PREFIX/built-at")
[ -e "$built_at" ] || { mkdir -p "$(dirname "$built_at")" && ln -s "$(pwd)" "$built_at"; }
[ -d "$VKB_PREFIX/scenes" ] && export VKPATH_SCENES_DIR="$VKB_PREFIX/scenes"
[ -e /usr/share/assimp/models ] || [ ! -d "$VKB_PREFIX/assimp" ] || { mkdir -p /usr/share/assimp && ln -s "$VKB_PREFIX/assimp/models" /usr/share/assimp/models; }
mkdir -p build/tests
for b in $(ls "$VKB_PREFIX/bin"); do
    w=build/$b
    [ "$b" = vkpath_tests ] && w=build/tests/$b
    printf '#!/bin/sh\nexec %s/lib/ld-linux-x86-64.so.2 --library-path %s/lib:%s/lib64:%s/lib %s/bin/%s "$@"\n' \
        "$VKB_PREFIX" "$VKB_PREFIX" "$NVIDIA_DIR" "$NVIDIA_DIR" "$VKB_PREFIX" "$b" > "$w"
    chmod +x "$w"
done
export VK_LAYER_PATH="$VKB_PREFIX/layers"
export XDG_RUNTIME_DIR=${TMPDIR:-/tmp}/vkpath-runtime VKPATH_CACHE_DIR=${TMPDIR:-/tmp}/vkpath-cache
mkdir -p "$XDG_RUNTIME_DIR" "$VKPATH_CACHE_DIR"
nvidia=$NVIDIA_DIR/share/vulkan/icd.d/nvidia_icd.json
if ! ls /usr/share/vulkan/icd.d/*.json /etc/vulkan/icd.d/*.json > /dev/null 2>&1 && [ -e "$nvidia" ]; then
    export VK_DRIVER_FILES=$nvidia VK_ICD_FILENAMES=$nvidia
fi
