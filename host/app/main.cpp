#include "app/cli.h"

int main(int argc, char** argv) {
    return vkpath::app::runCli(argc, argv);
}
