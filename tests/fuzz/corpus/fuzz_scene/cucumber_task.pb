
 (08"

cucumber*draftB-
+cut the cucumber at 0.3 ratio from the left