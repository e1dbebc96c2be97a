# Sourced from the repository root on the bare GPU machine (see pack): unpacks
# .devbundle/bundle.tar.xz into /opt/vkb and writes build/vkpath, build/vkpath-base and
# build/tests/vkpath_tests as wrappers that run the carried binaries through the carried
# loader; /work/main and /work/shared are made to point where the tests look (the paths they
# were compiled with). Refuses to run over a real build.
if [ -f build/vkpath ] && ! grep -q /opt/vkb build/vkpath 2>/dev/null; then
    echo "setup.sh: build/vkpath is a real build here; this is for the bare machine" >&2
    return 1 2>/dev/null || exit 1
fi
mkdir -p /opt/vkb
python3 -c "import tarfile; tarfile.open('.devbundle/bundle.tar.xz').extractall('/opt/vkb')"
[ -e /work/main ] || { mkdir -p /work && ln -s "$(pwd)" /work/main; }
[ -e /work/shared ] || ln -s /opt/vkb/shared /work/shared
[ -e /usr/share/assimp/models ] || [ ! -d /opt/vkb/assimp ] || { mkdir -p /usr/share/assimp && ln -s /opt/vkb/assimp/models /usr/share/assimp/models; }
mkdir -p build/tests
for b in $(ls /opt/vkb/bin); do
    w=build/$b
    [ "$b" = vkpath_tests ] && w=build/tests/$b
    printf '#!/bin/sh\nexec /opt/vkb/lib/ld-linux-x86-64.so.2 --library-path /opt/vkb/lib:/usr/local/nvidia/lib64:/usr/local/nvidia/lib /opt/vkb/bin/%s "$@"\n' "$b" > "$w"
    chmod +x "$w"
done
export VK_LAYER_PATH=/opt/vkb/layers
export XDG_RUNTIME_DIR=/tmp/vkpath-runtime VKPATH_CACHE_DIR=/tmp/vkpath-cache
mkdir -p "$XDG_RUNTIME_DIR" "$VKPATH_CACHE_DIR"
nvidia=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
if ! ls /usr/share/vulkan/icd.d/*.json /etc/vulkan/icd.d/*.json > /dev/null 2>&1 && [ -e $nvidia ]; then
    export VK_DRIVER_FILES=$nvidia VK_ICD_FILENAMES=$nvidia
fi
