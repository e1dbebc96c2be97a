#include <fmt/format.h>

#include <cstdio>

#include "app/commands.h"
#include "vk/context.h"

namespace vkpath::app {

int withContext(const GlobalOptions& global, const std::function<int(vk::Context&)>& body) {
    vk::ContextOptions options;
    options.validation = global.validation;
    options.deviceIndex = global.deviceIndex;
    vk::Context context(options);
    const int code = body(context);
    if (context.validationMessageCount() > 0) {
        std::fprintf(stderr, "vkpath: %u Vulkan validation message(s)\n",
                     context.validationMessageCount());
        return code == 0 ? 1 : code;
    }
    return code;
}

}  // namespace vkpath::app
