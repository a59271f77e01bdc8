; Example 1 of Colledanchise et al. 2019: move the cube onto the goal region. The path to the goal is
; free at the start; in the blended demo the sphere rolls into it at run time.
(define (problem cube-to-goal)
  (:domain cube-sphere)
  (:objects cube sphere - item
            goal - spot)
  (:init (hand-empty)
         (path-free cube) (path-free sphere) (path-free goal)
         (obstacle sphere))
  (:goal (and (at cube goal))))
