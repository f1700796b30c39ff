# Debian's libimgui-dev (1.86) ships a static libimgui.a that already contains the GLFW and OpenGL3
# backends, with its headers in /usr/include/imgui and a pkg-config file named `imgui`.
# This module turns that into the imported target ImGui::ImGui.
find_package(PkgConfig REQUIRED)
pkg_check_modules(PC_IMGUI QUIET imgui)

find_path(ImGui_INCLUDE_DIR imgui.h HINTS ${PC_IMGUI_INCLUDE_DIRS} PATH_SUFFIXES imgui)
find_library(ImGui_LIBRARY NAMES imgui HINTS ${PC_IMGUI_LIBRARY_DIRS})
find_library(ImGui_STB_LIBRARY NAMES stb HINTS ${PC_IMGUI_LIBRARY_DIRS})

include(FindPackageHandleStandardArgs)
find_package_handle_standard_args(ImGui REQUIRED_VARS ImGui_LIBRARY ImGui_INCLUDE_DIR VERSION_VAR PC_IMGUI_VERSION)

if(ImGui_FOUND AND NOT TARGET ImGui::ImGui)
    add_library(ImGui::ImGui STATIC IMPORTED)
    set_target_properties(ImGui::ImGui PROPERTIES
        IMPORTED_LOCATION "${ImGui_LIBRARY}"
        INTERFACE_INCLUDE_DIRECTORIES "${ImGui_INCLUDE_DIR}")
    # The backends inside libimgui.a load GL through dlopen; stb provides the font rasteriser.
    set(_imgui_links ${CMAKE_DL_LIBS})
    if(ImGui_STB_LIBRARY)
        list(APPEND _imgui_links ${ImGui_STB_LIBRARY})
    endif()
    set_property(TARGET ImGui::ImGui PROPERTY INTERFACE_LINK_LIBRARIES "${_imgui_links}")
endif()
