// Compares the ECP5 pixelproc_bank_ram (synth/ecp5/pixelproc_bank_ram.v on the DP16KD
// model synth/ecp5/sim/dp16kd_model.v) with the generic one the export carries, renamed
// `generic_bank_ram` by the test (testbench/tests/ecp5_bank_ram.rs), clock by clock under
// random writes and reads. First every word is written once in order, while reads pick
// words already written, then random traffic; a read never addresses the word written at the
// same edge (not defined on the DP16KD). Prints `PASS compared=N changes=M` or the first
// `MISMATCH`.
//   iverilog -g2012 -o tb tb_bank_ram.v GENERIC.v ../pixelproc_bank_ram.v dp16kd_model.v
//   vvp tb +seed=1 +cycles=20000
module tb_bank_ram;
    reg clock = 1'b0;
    reg write_enable = 1'b0;
    reg [9:0] write_address = 10'h0;
    reg [17:0] write_data = 18'h0;
    reg [9:0] read_address = 10'h0;
    wire [17:0] generic_data, ecp5_data;
    integer seed, cycles, t, compared, changes;
    reg [17:0] last;
    reg [31:0] r;

    generic_bank_ram generic(.clock(clock), .write_enable(write_enable), .write_address(write_address),
        .write_data(write_data), .read_address(read_address), .read_data(generic_data));
    pixelproc_bank_ram ecp5(.clock(clock), .write_enable(write_enable), .write_address(write_address),
        .write_data(write_data), .read_address(read_address), .read_data(ecp5_data));

    always #5 clock = ~clock;

    initial begin
        if (!$value$plusargs("seed=%d", seed)) seed = 1;
        if (!$value$plusargs("cycles=%d", cycles)) cycles = 20000;
        compared = 0;
        changes = 0;
        last = 18'h0;
        for (t = 0; t < 1024 + cycles; t = t + 1) begin
            @(negedge clock);
            r = $random(seed);
            if (t < 1024) begin
                write_enable = 1'b1;
                write_address = t[9:0];
            end else begin
                write_enable = r[0];
                // Half of the time a narrow window: the same words written and read often.
                write_address = r[1] ? {7'h0, r[4:2]} : r[14:5];
            end
            write_data = $random(seed);
            r = $random(seed);
            if (t < 1024) read_address = (t == 0) ? 10'h0 : r[30:0] % t;   // words written
            else read_address = r[0] ? {7'h0, r[3:1]} : r[13:4];
            if (write_enable && read_address == write_address) read_address = read_address ^ 10'h1;
            @(posedge clock);
            #1;
            // The output after edge t is the word read at edge t - 1 (from the second edge
            // on, a written word).
            if (t >= 2) begin
                if (generic_data !== ecp5_data || ^ecp5_data === 1'bx) begin
                    $display("MISMATCH cycle=%0d generic=%h ecp5=%h", t, generic_data, ecp5_data);
                    $finish;
                end
                compared = compared + 1;
                if (ecp5_data != last) changes = changes + 1;
                last = ecp5_data;
            end
        end
        $display("PASS compared=%0d changes=%0d", compared, changes);
        $finish;
    end
endmodule
