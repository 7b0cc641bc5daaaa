!> The sweep scheduler's order: costliest case first, ties in case order, skipped cases left out.
program test_sweep
  use kinds, only: dp
  use testing, only: check, test_summary
  use sweep, only: case_cost_order
  implicit none
  real(dp), parameter :: COST(5) = [1.0_dp, 5.0_dp, 3.0_dp, 5.0_dp, 2.0_dp]
  logical, parameter :: RUN(5) = [.true., .true., .true., .true., .false.]
  call check(size(case_cost_order(COST, RUN)) == 4, 'order: the skipped case is left out')
  call check(all(case_cost_order(COST, RUN) == [2, 4, 3, 1]), 'order: decreasing cost, ties in case order')
  call check(size(case_cost_order(COST(1:0), RUN(1:0))) == 0, 'order: no case')
  call test_summary('sweep')
end program test_sweep
