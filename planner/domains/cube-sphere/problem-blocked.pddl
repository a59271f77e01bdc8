; Example 2 of Colledanchise et al. 2019, planned offline: the sphere already blocks the path to the
; goal. Planning expands `path-free goal`, finds that clearing the path needs an empty
; hand while the branch before it leaves the cube in the hand, and moves the new
; subtree left and up until the tree is conflict-free: the arrangement of Fig. 4. From
; this state the hand is empty whenever the tree checks it, so `hand-empty` is never
; expanded; Example 2's drop comes from expanding at run time with the cube in the hand
; (`sim-host plan ... --expand-at 'holding(cube), not hand-empty'`, the firmware's tree).
; Same objects in the same order as problem.pddl (cube=0, sphere=1, goal=2).
(define (problem cube-to-goal-blocked)
  (:domain cube-sphere)
  (:objects cube sphere - item
            goal - spot)
  (:init (hand-empty)
         (path-free cube) (path-free sphere)
         (obstacle sphere))
  (:goal (and (at cube goal))))
