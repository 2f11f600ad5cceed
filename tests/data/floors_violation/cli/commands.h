// The top floor of the deliberately broken tree (tests/CMakeLists.txt, Layout.FloorsRefuseAnUpwardInclude).
#pragma once
