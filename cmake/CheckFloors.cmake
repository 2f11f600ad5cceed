# The floors of host/ (docs/design.md), bottom up: a folder may include only folders on lower floors
# (and itself). Folders on one floor do not include each other.
#
# sdfbrick_check_floors(SOURCE_DIR <host dir>) adds the target check_floors, built with everything,
# which fails the build naming every file and include that goes up or sideways. Script mode
# (cmake -DHOST_DIR=<host dir> -P CheckFloors.cmake) runs the check; CTest runs it as Layout.Floors.

cmake_policy(VERSION 3.25)
set(SDFBRICK_FLOORS "core|cl,scene,image|measure|construct|reference,bvh|render|exchange,pipeline|tune|sweep|cli,python")

function(sdfbrick_floor_of folder out)
    string(REPLACE "|" ";" floors "${SDFBRICK_FLOORS}")
    set(floor 0)
    foreach(line IN LISTS floors)
        string(REPLACE "," ";" names "${line}")
        if(folder IN_LIST names)
            set(${out} ${floor} PARENT_SCOPE)
            return()
        endif()
        math(EXPR floor "${floor} + 1")
    endforeach()
    set(${out} -1 PARENT_SCOPE)
endfunction()

if(CMAKE_SCRIPT_MODE_FILE)
    file(GLOB_RECURSE files RELATIVE "${HOST_DIR}" "${HOST_DIR}/*.h" "${HOST_DIR}/*.cpp")
    set(errors "")
    foreach(f IN LISTS files)
        string(REGEX MATCH "^[^/]+" folder "${f}")
        if(folder STREQUAL f)
            continue()  # a file at the top of host/
        endif()
        sdfbrick_floor_of("${folder}" from)
        if(from EQUAL -1)
            string(APPEND errors "  host/${f}: folder ${folder}/ is on no floor (add it to cmake/CheckFloors.cmake and docs/design.md)\n")
            continue()
        endif()
        file(STRINGS "${HOST_DIR}/${f}" includes REGEX "^[ \t]*#[ \t]*include[ \t]+\"[^\"/]+/")
        foreach(line IN LISTS includes)
            string(REGEX REPLACE "^[ \t]*#[ \t]*include[ \t]+\"([^\"/]+)/.*" "\\1" target "${line}")
            if(target STREQUAL folder)
                continue()
            endif()
            sdfbrick_floor_of("${target}" to)
            if(to EQUAL -1 OR NOT to LESS from)
                string(STRIP "${line}" line)
                string(APPEND errors "  host/${f}: ${line} (${folder}/ may include only folders on floors below it)\n")
            endif()
        endforeach()
    endforeach()
    if(errors)
        message(FATAL_ERROR "host/ folders include upwards or sideways (floors: ${SDFBRICK_FLOORS}):\n${errors}")
    endif()
    return()
endif()

function(sdfbrick_check_floors)
    cmake_parse_arguments(ARG "" "SOURCE_DIR" "" ${ARGN})
    file(GLOB_RECURSE sources CONFIGURE_DEPENDS "${ARG_SOURCE_DIR}/*.h" "${ARG_SOURCE_DIR}/*.cpp")
    set(stamp "${CMAKE_CURRENT_BINARY_DIR}/floors.stamp")
    add_custom_command(
        OUTPUT "${stamp}"
        COMMAND "${CMAKE_COMMAND}" -DHOST_DIR=${ARG_SOURCE_DIR} -P "${CMAKE_CURRENT_FUNCTION_LIST_FILE}"
        COMMAND "${CMAKE_COMMAND}" -E touch "${stamp}"
        DEPENDS ${sources} "${CMAKE_CURRENT_FUNCTION_LIST_FILE}"
        COMMENT "Checking that no host/ folder includes a folder above it"
        VERBATIM)
    add_custom_target(check_floors ALL DEPENDS "${stamp}")
endfunction()
