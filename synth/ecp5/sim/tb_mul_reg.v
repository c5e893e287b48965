// Compares the ECP5 pixelproc_mul_reg (synth/ecp5/pixelproc_mul_reg.v on the MULT18X18D
// model synth/ecp5/sim/mult18x18d_model.v) with the generic one the export carries,
// renamed `generic_mul_reg` by the test (testbench/tests/ecp5_mul_reg.rs), clock by clock
// under random operands (a quarter of them at the extremes 0 and 0xffff). Prints
// `PASS compared=N changes=M` or the first `MISMATCH`.
//   iverilog -g2012 -o tb tb_mul_reg.v GENERIC.v ../pixelproc_mul_reg.v mult18x18d_model.v
//   vvp tb +seed=1 +cycles=20000
module tb_mul_reg;
    reg clock = 1'b0;
    reg [15:0] a = 16'h0;
    reg [15:0] b = 16'h0;
    wire [31:0] generic_p, ecp5_p;
    integer seed, cycles, t, compared, changes;
    reg [31:0] last;
    reg [31:0] r;

    generic_mul_reg generic(.clock(clock), .a(a), .b(b), .p(generic_p));
    pixelproc_mul_reg ecp5(.clock(clock), .a(a), .b(b), .p(ecp5_p));

    always #5 clock = ~clock;

    initial begin
        if (!$value$plusargs("seed=%d", seed)) seed = 1;
        if (!$value$plusargs("cycles=%d", cycles)) cycles = 20000;
        compared = 0;
        changes = 0;
        last = 32'h0;
        for (t = 0; t < cycles; t = t + 1) begin
            @(negedge clock);
            r = $random(seed);
            a = r[15:0];
            b = r[31:16];
            r = $random(seed);
            if (r[1:0] == 2'b00) a = r[2] ? 16'hffff : 16'h0;
            if (r[4:3] == 2'b00) b = r[5] ? 16'hffff : 16'h0;
            @(posedge clock);
            #1;
            // Compared from power-on: both start with every register at zero.
            if (generic_p !== ecp5_p || ^ecp5_p === 1'bx) begin
                $display("MISMATCH cycle=%0d generic=%h ecp5=%h", t, generic_p, ecp5_p);
                $finish;
            end
            compared = compared + 1;
            if (ecp5_p != last) changes = changes + 1;
            last = ecp5_p;
        end
        $display("PASS compared=%0d changes=%0d", compared, changes);
        $finish;
    end
endmodule
