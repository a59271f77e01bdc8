; The chassis and the battery lie front up where only the left arm reaches them: each
; is picked by the front and handed over to the right (assembling) arm. The camera is
; in reach of both arms.
(define (problem assemble-phone)
  (:domain cellphone)
  (:objects left right - arm
            chassis board camera battery screen - part)
  (:init (free left) (free right)
         (on-table chassis) (on-table board) (on-table camera) (on-table battery) (on-table screen)
         (reaches left chassis) (reaches left battery) (reaches left camera)
         (reaches right board) (reaches right camera) (reaches right screen)
         (front-up chassis) (front-up battery)
         (back-up board) (back-up camera) (back-up screen)
         (assembler right) (other left right) (other right left)
         (base chassis)
         (mounts-on board chassis) (mounts-on camera board) (mounts-on battery board)
         (mounts-on screen battery))
  (:goal (and (mounted chassis) (mounted board) (mounted camera) (mounted battery) (mounted screen))))
