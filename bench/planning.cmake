# bench_planning links OMPL (RRT* side by side with Hybrid A*).
if(TARGET bench_planning)
  find_package(ompl REQUIRED)
  target_link_libraries(bench_planning PRIVATE ${OMPL_LIBRARIES})
  target_include_directories(bench_planning SYSTEM PRIVATE ${OMPL_INCLUDE_DIRS})
endif()
