# One place for squint's per-target settings: module libraries and warnings.

# Warnings for squint's own targets only; nothing is pushed onto users.
function(squint_set_warnings target)
  target_compile_features(${target} PUBLIC cxx_std_20)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Wshadow)
endfunction()

# squint_add_module(NAME PUBLIC_DEPS ... PRIVATE_DEPS ...): a library squint_NAME with alias
# squint::NAME from src/NAME/*.cpp and headers under include/squint/NAME/. A module with no
# sources yet is an INTERFACE library so that dependants still link.
function(squint_add_module name)
  cmake_parse_arguments(ARG "" "" "PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  file(GLOB _srcs CONFIGURE_DEPENDS ${PROJECT_SOURCE_DIR}/src/${name}/*.cpp)
  if(_srcs)
    add_library(squint_${name} STATIC ${_srcs})
    target_include_directories(squint_${name} PUBLIC
      $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include> $<INSTALL_INTERFACE:include>
      PRIVATE ${PROJECT_SOURCE_DIR}/src)
    target_link_libraries(squint_${name} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
    set_target_properties(squint_${name} PROPERTIES POSITION_INDEPENDENT_CODE ON)
    squint_set_warnings(squint_${name})
  else()
    add_library(squint_${name} INTERFACE)
    target_include_directories(squint_${name} INTERFACE
      $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include> $<INSTALL_INTERFACE:include>)
    target_link_libraries(squint_${name} INTERFACE ${ARG_PUBLIC_DEPS})
    target_compile_features(squint_${name} INTERFACE cxx_std_20)
  endif()
  set_target_properties(squint_${name} PROPERTIES EXPORT_NAME ${name})
  add_library(squint::${name} ALIAS squint_${name})
  install(TARGETS squint_${name} EXPORT squintTargets ARCHIVE DESTINATION lib LIBRARY DESTINATION lib)
endfunction()
